"""Reading flapwing MCAP logs and ROS 2 bags: every channel (topic) as a dict of numpy
arrays, or as a pandas DataFrame when pandas is installed and asked for. The decoding is
flightlog's own (Rust), the same as ``flapwing replay``'s."""

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

    Each table has ``log_time_ns`` (int64) and one column per message field by its dotted
    path; numeric columns are float64 arrays (NaN where a message lacks the field), others
    lists of str (None where missing). ``path`` may also be a ROS 2 bag (MCAP with
    ``ros2msg`` schemas and CDR messages, as rosbag2 writes): one table per topic with the
    columns of ``flapwing replay BAG --csv TOPIC`` (``header.stamp.sec``,
    ``pose.position.x``, array elements ``transforms.0.child_frame_id``), in the same shape.
    A bag topic that cannot be decoded (a type its schema does not define, a message shorter
    than its type) raises ``ValueError`` with the error the CLI gives.

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
