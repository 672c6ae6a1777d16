"""Schema of the raw interaction dataset (one row per step), before discretization.

A raw dataset is a :class:`pandas.DataFrame` (stored as Parquet) with the
columns below; :func:`a2l.skills.Discretizer.discretize` turns it into the discrete dataset a
Bayesian network is learned from.

==================================  =========  ==============================================
column                              dtype      meaning
==================================  =========  ==============================================
``episode``                         int        trajectory (interaction) id
``step``                            int        index of the step within its episode
``eef_x``, ``eef_y``, ``eef_z``     float      end-effector position before the step (m)
``obj_x``, ``obj_y``, ``obj_z``     float      object position before the step (m)
``move_dx``, ``move_dy``,           float      end-effector displacement during the step (m),
``move_dz``                                    or a velocity (only its direction is used)
``effect_dx``, ``effect_dy``,       float      object displacement the row is labelled with
``effect_dz``                                  (the episode's observed effect), **or**
``effect``                          str        the effect's name, when it is known already
high-level states (optional)        str        one column per state (e.g. ``light``)
``action`` (optional)               str        an action of the repertoire (``open``,
                                               ``close``, ``stay``) the row took instead of
                                               its displacement; empty or None otherwise
==================================  =========  ==============================================

Positions are in the robot's base frame: x forward (away from the robot), y to the left,
z up; the table plane is z = constant.
"""

from __future__ import annotations

from collections.abc import Iterable

import pandas as pd

__all__ = [
    "DATASET_SCHEMA_VERSION",
    "EFFECT_DISPLACEMENT_COLUMNS",
    "EEF_COLUMNS",
    "MOVE_COLUMNS",
    "OBJECT_COLUMNS",
    "REQUIRED_COLUMNS",
    "check_columns",
]

#: Version of this schema, written into a Parquet file's metadata.
DATASET_SCHEMA_VERSION = 1

EEF_COLUMNS = ("eef_x", "eef_y", "eef_z")
OBJECT_COLUMNS = ("obj_x", "obj_y", "obj_z")
MOVE_COLUMNS = ("move_dx", "move_dy", "move_dz")
EFFECT_DISPLACEMENT_COLUMNS = ("effect_dx", "effect_dy", "effect_dz")
REQUIRED_COLUMNS = ("episode", "step", *EEF_COLUMNS, *OBJECT_COLUMNS, *MOVE_COLUMNS)


def check_columns(df: pd.DataFrame, columns: Iterable[str], what: str = "dataset") -> None:
    """Raise ``ValueError`` naming every column of `columns` missing from `df`.

    Parameters
    ----------
    df : pandas.DataFrame
        The table to check.
    columns : iterable of str
        Column names it must have.
    what : str
        How to call `df` in the message.
    """
    missing = [c for c in columns if c not in df.columns]
    if missing:
        raise ValueError(
            f"{what} is missing column(s) {missing}; it has {list(map(str, df.columns))}"
        )
