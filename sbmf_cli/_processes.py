"""Processes of a run: interrupts, the local worker pool, and the CPUs a run may use."""

from __future__ import annotations

import contextlib
import ctypes
import functools
import os
import signal
import sys
import threading
import time
from concurrent.futures import ProcessPoolExecutor

from ._errors import interrupted_line

__all__ = [
    "Interrupted",
    "available_cpus",
    "interruptible",
    "process_pool",
    "process_seconds",
    "worker_ignores_interrupts",
]

#: when this module was imported (the run time's start where the process's own is unknown)
_IMPORTED = time.perf_counter()


def process_seconds():
    """Seconds since this process started: what a user's wall clock shows for a command so far.

    On Linux from the process's start time (``/proc/self/stat``, 10 ms ticks), so that the
    interpreter's start and the imports count, as they do on the user's clock; elsewhere since
    the command layer was imported (early in every command).
    """
    try:
        with open("/proc/self/stat", encoding="ascii") as fh:
            start_ticks = int(fh.read().rsplit(")", 1)[1].split()[19])  # field 22, starttime
        with open("/proc/uptime", encoding="ascii") as fh:
            uptime = float(fh.read().split()[0])
        return max(0.0, uptime - start_ticks / os.sysconf("SC_CLK_TCK"))
    except (OSError, ValueError, IndexError, AttributeError):
        return time.perf_counter() - _IMPORTED


def available_cpus():
    """CPUs this process may run on, on every platform.

    The process's CPU affinity where the system has one (``os.sched_getaffinity``: Linux, a
    container's or ``taskset``'s limit included); else ``os.process_cpu_count()`` (Python 3.13+)
    or ``os.cpu_count()`` (macOS, Windows); at least 1.
    """
    affinity = getattr(os, "sched_getaffinity", None)
    if affinity is not None:
        try:
            return max(1, len(affinity(0)))
        except OSError:  # pragma: no cover - affinity not readable here
            pass
    count = getattr(os, "process_cpu_count", None) or os.cpu_count
    return max(1, count() or 1)


class Interrupted(BaseException):
    """SIGTERM (or another handled signal) turned into an exception, like KeyboardInterrupt."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


#: how long the main thread may run on, handling no exception, after an interrupt was raised
#: before the interrupt counts as swallowed and is delivered again (s)
REDELIVER_AFTER = 0.2


def _handling(main_ident):
    """Whether the main thread is handling an exception now (in an ``except`` or ``finally``)."""
    current = getattr(sys, "_current_exceptions", None)
    if current is None:  # pragma: no cover - not CPython: never count an interrupt as lost
        return True
    exc = current().get(main_ident)
    return exc is not None and (exc[0] is not None if isinstance(exc, tuple) else True)


def numba_compiling():
    """Whether this thread holds numba's compiler lock (compiling, or loading from its cache).

    An exception raised inside numba's compiler leaves its state half-built: measured with a
    Ctrl-C 1.5 s into a calibration on a fresh clone (the kernels compiling), a ``RuntimeError``
    "no compiled object yet" with a traceback instead of the interrupt, and in 1 of 6 runs a
    segmentation fault. So the handler does not raise there; the watcher delivers the signal
    again (every :data:`REDELIVER_AFTER` s) and it is raised once the compilation is done.
    """
    mod = sys.modules.get("numba.core.compiler_lock")
    if mod is None:
        return False
    try:
        return bool(mod.global_compiler_lock.is_locked())
    except Exception:  # pragma: no cover - another numba: never hold an interrupt back
        return False


class _Interrupts:
    """The signal handlers of one interruptible run, which make sure an interrupt arrives.

    Python runs a signal's handler at the next instruction of the main thread, wherever that is;
    an exception raised inside a weakref callback or a ``__del__`` (the import system runs such
    callbacks all the time) is printed as "Exception ignored" and the program goes on: a Ctrl-C
    during the imports of numba was lost that way in 1 of 4 runs. So the handler raises and
    watches: where the main thread runs on for :data:`REDELIVER_AFTER` seconds without handling
    any exception (not unwinding through ``finally`` or ``except`` blocks, where the run cleans
    up), the interrupt was swallowed and the signal is sent again. An interrupt swallowed at
    the very end, after the command returned, makes the run interrupted all the same. A
    swallowed interrupt is not printed (:meth:`unraisable`): it is delivered again, and its
    "Exception ignored" traceback (measured: a SIGINT that arrived while the main process forked
    a pool worker, inside the ``logging`` module's after-fork hook) would be a traceback for a
    user's Ctrl-C.
    """

    def __init__(self):
        self.signum = None  # the interrupt raised last
        self.handled = False
        self.watcher = None
        self.main_ident = threading.main_thread().ident

    def __call__(self, signum, frame):
        self.signum = signum
        if self.watcher is None:
            self.watcher = threading.Thread(target=self._watch, daemon=True)
            self.watcher.start()
        if numba_compiling():
            return  # the watcher sends the signal again until the compilation is done
        if signum == signal.SIGINT:
            raise KeyboardInterrupt
        raise Interrupted(signum)

    def unraisable(self, previous):
        """A ``sys.unraisablehook`` dropping this handler's interrupts; else ``previous``."""

        def hook(unraisable):
            exc = unraisable.exc_value
            if self.signum is not None and isinstance(exc, (KeyboardInterrupt, Interrupted)):
                return  # swallowed: the watcher delivers the signal again
            previous(unraisable)

        return hook

    def _watch(self):
        quiet = 0.0
        step = REDELIVER_AFTER / 4
        while not self.handled:
            time.sleep(step)
            quiet = 0.0 if _handling(self.main_ident) else quiet + step
            signum = self.signum
            if quiet >= REDELIVER_AFTER - 1e-9 and not self.handled and signum is not None:
                quiet = 0.0
                os.kill(os.getpid(), signum)


def interruptible(prog, what):
    """Decorate a command's ``main`` so that SIGINT and SIGTERM end it cleanly.

    Ctrl-C (SIGINT, to the process group or to this process alone) and SIGTERM raise in the
    main process (SIGTERM through :class:`Interrupted`); the run's own cleanup runs on the way
    out (its temporary output folder is deleted, an earlier output is left as it was, worker
    processes are ended by the pool), and the command prints one line and returns
    ``128 + signal number`` (130 for SIGINT, 143 for SIGTERM), without a traceback. An
    interrupt that Python swallowed (raised inside a weakref callback of the import system) is
    delivered again (:class:`_Interrupts`). A SIGINT the process was started to ignore (a
    background job) stays ignored.
    """

    def wrap(main):
        @functools.wraps(main)
        def run(argv=None):
            in_main = threading.current_thread() is threading.main_thread()
            handler = _Interrupts()
            old = {}
            hook = sys.unraisablehook
            if in_main:
                sys.unraisablehook = handler.unraisable(hook)
                old[signal.SIGTERM] = signal.signal(signal.SIGTERM, handler)
                current = signal.getsignal(signal.SIGINT)
                if current is signal.default_int_handler or isinstance(current, _Interrupts):
                    old[signal.SIGINT] = signal.signal(signal.SIGINT, handler)
            try:
                code = main(argv)
                if handler.signum is None:
                    return code
                signum = handler.signum  # swallowed, and the run went on to its end
            except (KeyboardInterrupt, Interrupted) as exc:
                signum = getattr(exc, "signum", signal.SIGINT)
            except Exception:
                if handler.signum is None:
                    raise
                # the interrupt in disguise: Python wraps an exception raised inside some hooks
                # (a class body's __set_name__: "RuntimeError: Error calling __set_name__",
                # measured with a Ctrl-C during an import), and the user pressed Ctrl-C
                signum = handler.signum
            finally:
                handler.handled = True
                for sig, previous in old.items():
                    signal.signal(sig, previous)
                if in_main:
                    sys.unraisablehook = hook
            print(interrupted_line(prog, what, signum), file=sys.stderr)
            return 128 + int(signum)

        return run

    return wrap


def worker_ignores_interrupts():
    """Set up a worker process of a command's pool so that interrupts stay the main process's.

    Ctrl-C reaches the whole process group: the worker ignores SIGINT (no traceback of its own)
    and is ended by the main process (:func:`process_pool`). SIGTERM ends it at once (the default
    action, not an inherited handler), and on Linux the kernel sends it SIGTERM when the main
    process dies (``PR_SET_PDEATHSIG``), so that no worker outlives its run.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, int(signal.SIGTERM))  # PR_SET_PDEATHSIG = 1
        except (OSError, AttributeError):  # pragma: no cover - no prctl here
            pass


def _init_pool_worker(initializer, initargs):
    worker_ignores_interrupts()
    if initializer is not None:
        initializer(*initargs)


@contextlib.contextmanager
def process_pool(max_workers, initializer=None, initargs=()):
    """A ``ProcessPoolExecutor`` that an interrupt ends at once, workers included.

    On the way out of the block with an exception (Ctrl-C, SIGTERM as :class:`Interrupted`, a
    failed job) the pending jobs are cancelled and the running workers terminated: the
    executor's own ``shutdown(wait=True)`` would wait for workers that keep computing. Without an
    exception the pool is shut down normally. The workers run :func:`worker_ignores_interrupts`
    before ``initializer(*initargs)``.
    """
    pool = ProcessPoolExecutor(
        max_workers=max_workers, initializer=_init_pool_worker, initargs=(initializer, initargs)
    )
    try:
        yield pool
    except BaseException:
        procs = list((getattr(pool, "_processes", None) or {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for p in procs:
            if p.is_alive():
                p.terminate()
        for p in procs:
            p.join(timeout=5)
            if p.is_alive():
                p.kill()
        raise
    pool.shutdown(wait=True)
