"""Interaction datasets: schema, reading, writing (see :mod:`a2l.data.schema`)."""

from __future__ import annotations

from a2l.data.schema import (
    DATASET_SCHEMA_VERSION,
    EEF_COLUMNS,
    EFFECT_DISPLACEMENT_COLUMNS,
    MOVE_COLUMNS,
    OBJECT_COLUMNS,
    REQUIRED_COLUMNS,
    check_columns,
)

__all__ = [
    "DATASET_SCHEMA_VERSION",
    "EEF_COLUMNS",
    "EFFECT_DISPLACEMENT_COLUMNS",
    "MOVE_COLUMNS",
    "OBJECT_COLUMNS",
    "REQUIRED_COLUMNS",
    "check_columns",
]
