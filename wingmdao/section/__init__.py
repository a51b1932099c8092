"""wingmdao.section."""
