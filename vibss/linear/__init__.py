"""The numerical core: assembly, named signals, the Plant, the eigen path, the exact solve, state space.

Every analysis package (:mod:`vibss.modal`, :mod:`vibss.frequency`, :mod:`vibss.time`,
:mod:`vibss.reduction`) stands on the modules here; nothing here imports an analysis.
"""
