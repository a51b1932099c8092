"""Test-session defaults.

Compiled CasADi functions (wingmdao.utils.casadi_cache) switch on in the background after a few
thousand evaluations; the suite runs interpreted so every test sees one code path (results are
the same to round-off) and CI does not spend its second core on gcc. tests/test_casadi_cache.py
turns compilation on explicitly, with a temporary cache folder.
"""

import os

os.environ.setdefault("WINGMDAO_JIT", "0")
