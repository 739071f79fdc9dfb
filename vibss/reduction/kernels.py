"""Kernels of :mod:`vibss.reduction`: exact pruning (:mod:`.prune`), modal truncation
(:mod:`.truncation`), rational Krylov projection (:mod:`.krylov`), plus the exact response used to check reductions (:func:`frf`)."""

from __future__ import annotations

from .prune import (DENSE_MAX, PART_RTOL, ZERO_RTOL, Removal, frf, modal_plant, prune_dofs, prune_modes,
                    sub_plant)
from .krylov import KrylovBasis, as_sparse, exact_response, krylov, prune_sparse, sparse_plant
from .truncation import CHECK_SAFETY, N_CHECK, SPARSE_MODES_MAX, Truncation, truncate

__all__ = ["KrylovBasis", "as_sparse", "exact_response", "krylov", "prune_sparse", "sparse_plant",
           "CHECK_SAFETY", "DENSE_MAX", "N_CHECK", "PART_RTOL", "Removal", "SPARSE_MODES_MAX",
           "Truncation", "ZERO_RTOL", "frf", "modal_plant", "prune_dofs", "prune_modes", "sub_plant",
           "truncate"]
