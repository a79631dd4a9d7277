"""Helpers every layer may use: input checks and the job runner. Imports nothing of the package."""

from .checks import count, pair, positive
from .jobs import JobResult, run_jobs

__all__ = ["JobResult", "count", "pair", "positive", "run_jobs"]
