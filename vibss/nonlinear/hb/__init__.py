"""Harmonic balance kernels: the linear part condensed onto the nonlinear mount axes
(:mod:`.condensed`), the alternating frequency-time evaluation of their forces (:mod:`.aft`), the
residual and its pseudo-arclength continuation (:mod:`.continuation`) and the stability by Floquet
multipliers (:mod:`.floquet`) or Hill's method (:mod:`.hill`). The public function is
:func:`vibss.nonlinear.harmonic.harmonic_balance`."""
