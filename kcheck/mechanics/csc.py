"""Compressed-sparse-column matrices as clarabel reads them, built with numpy alone.

clarabel takes its constraint matrices as scipy ``csc_matrix`` objects, but reads only their
attributes; scipy's construction and validation cost more than the small conic programmes'
solves (:mod:`kcheck.mechanics.statics`, :mod:`kcheck.mechanics.cones`).
"""

from __future__ import annotations

import numpy as np

from kcheck.records import dataclass

__all__ = ["Csc"]


@dataclass(frozen=True)
class Csc:
    """A compressed-sparse-column matrix as clarabel reads it (the attributes of scipy's
    ``csc_matrix``): the same nonzeros in the same order as ``csc_matrix(dense)``, without
    scipy's validation, which cost more than clarabel's solve."""

    shape: tuple[int, int]
    indptr: np.ndarray
    indices: np.ndarray
    data: np.ndarray
    format: str = "csc"
    has_canonical_format: bool = True
    has_sorted_indices: bool = True

    @property
    def nnz(self) -> int:
        """Stored nonzeros."""
        return len(self.data)

    @classmethod
    def of(cls, dense: np.ndarray) -> Csc:
        """The nonzeros of ``dense`` by column, rows ascending within each."""
        cols, rows = np.nonzero(dense.T)
        indptr = np.zeros(dense.shape[1] + 1, np.int64)
        np.cumsum(np.bincount(cols, minlength=dense.shape[1]), out=indptr[1:])
        return cls(dense.shape, indptr, rows.astype(np.int64), dense.T[cols, rows])

    @classmethod
    def empty(cls, size: int) -> Csc:
        """The ``size`` x ``size`` zero matrix."""
        zero = np.zeros(0, np.int64)
        return cls((size, size), np.zeros(size + 1, np.int64), zero, np.zeros(0))
