"""run_problem: the solid rectangular cantilever of Sec. 4.7.1 sized under static and suddenly
applied tip loads (Table 4.25: the dynamic optimum is heavier), from the three initial guesses.

    python cases/run_cantilever.py
"""

from wingmdao.cases import cantilever
from wingmdao.sizing import size_case

for load in ("static", "step"):
    for guess in ("a", "b", "c"):
        setup = cantilever.build(load=load, guess=guess)
        setup.options.disp = False
        prob, res = size_case(setup)
        print(f"{load:6s} guess {guess}: mass {res['mass_kg']:10.1f} kg  iterations {res['iterations']:3d}  "
              f"max KS {res['max_ks']:+.2e}  {res['wall_s']:.1f} s")
