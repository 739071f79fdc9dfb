"""Projection bases: Krylov and the channel subspace."""
