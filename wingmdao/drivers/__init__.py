"""OpenMDAO drivers that wingmdao adds (imported lazily by :func:`wingmdao.optimize.make_driver`)."""
