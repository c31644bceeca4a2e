"""Layer 5, the analyses: the one harmonic kernel (:mod:`.kernel`) and what is built on it
(:mod:`.stationary`, :mod:`.sweep`), :mod:`.modes`, :mod:`.simulate` and the nonlinear
steady state (:mod:`.harmonic_balance`, :mod:`.periodic`, :mod:`.backbone`).  Every
analysis takes a :class:`~resonant.system.LinearSystem` and returns a frozen result.

The package imports none of its modules: a command loads only the analyses it runs
(``resonant solve`` needs neither simulation nor harmonic balance).
"""
