"""wingmdao.timemarch."""
