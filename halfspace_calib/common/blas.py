"""One BLAS thread for the fits' small dense algebra, so that a result is the same in every process.

The fits (``scipy.optimize.least_squares``, SLSQP) run dense products on matrices of a few
parameters by some hundred residuals. OpenBLAS splits such products over its threads, and the
rounding then depends on their number: measured, a four-patch calibration's ``C1`` differed in the
ninth digit between ``OPENBLAS_NUM_THREADS=1`` (as in a Dask worker, which pins one thread) and 2.
With one thread the fits give the same digits in this process, in a process-pool worker and in a
Dask worker; at these sizes one thread is also not slower. ``threadpoolctl`` (the library
scikit-learn uses for the same purpose) sets the limit for the ``with`` block only.
"""

import functools

from threadpoolctl import threadpool_limits

__all__ = ["serial_blas"]


def serial_blas(func):
    """Decorator: ``func`` runs with BLAS limited to one thread (restored afterwards)."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        with threadpool_limits(limits=1, user_api="blas"):
            return func(*args, **kwargs)

    return wrapper
