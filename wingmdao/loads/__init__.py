"""wingmdao.loads."""
