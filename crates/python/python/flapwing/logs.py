"""Reading flapwing MCAP logs: every channel as a dict of numpy arrays, or as a pandas
DataFrame when pandas is installed and asked for. The decoding is flightlog's own (Rust)."""

from __future__ import annotations

import warnings
from typing import Any

from ._flapwing import log_damage, log_topics, read_channel

__all__ = ["TruncatedLogWarning", "read_log"]


class TruncatedLogWarning(UserWarning):
    """A log is truncated or damaged (a killed run): ``read_log`` returns what it recovered."""


def read_log(path: str, topics: list[str] | None = None, pandas: bool | None = None
             ) -> dict[str, Any]:
    """{topic: {column: numpy array}} for the log at ``path`` (all topics, or ``topics``).

    With ``pandas=True`` each channel is a ``pandas.DataFrame``; ``None`` (the default)
    gives DataFrames when pandas is importable and dicts otherwise. Raises ``OSError`` for
    a file that cannot be read and ``ValueError`` for one that is not a flapwing MCAP log
    or lacks a topic. A truncated or damaged log (a killed run) gives what it holds up to
    its last complete chunk, with a ``TruncatedLogWarning`` that says where it ends and how
    much was recovered.
    """
    damage = log_damage(path)
    if damage is not None:
        warnings.warn(f"{path}: {damage}", TruncatedLogWarning, stacklevel=2)
    names = list(topics) if topics is not None else log_topics(path)
    out = {t: read_channel(path, t) for t in names}
    if pandas is False:
        return out
    try:
        import pandas as pd
    except ImportError:
        if pandas:
            raise
        return out
    return {t: pd.DataFrame(cols) for t, cols in out.items()}
