"""wingmdao.timemarch: residual systems, Newton, BDF time marching and the discrete adjoint.

* :mod:`~wingmdao.timemarch.system`: ``VarSpec``, ``layout``, ``pack``, ``ResidualSystem``,
  ``CasadiResidualSystem``;
* :mod:`~wingmdao.timemarch.newton`: ``newton_solve``, ``NewtonInfo``;
* :mod:`~wingmdao.timemarch.bdf`: ``march``, ``solve_static``, ``time_step``, ``state_rates``;
* :mod:`~wingmdao.timemarch.adjoint`: ``LinearizedHistory`` (tangent and adjoint sweeps);
* :mod:`~wingmdao.timemarch.examples`: spring-mass-damper (Sec. 4.6.1) and a nonlinear chain.

See ``docs/time-marching.md``.
"""
