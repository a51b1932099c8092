"""run_problem: the CRM wing (App. D.3) sized for the 2.5 g and -1.0 g maneuvers.

    python cases/run_crm.py
"""

import os

from wingmdao.cases import crm
from wingmdao.results import write_case_plots
from wingmdao.sizing import size_case

setup = crm.build()
os.makedirs("results", exist_ok=True)
setup.options.recording = "results/crm.sql"
prob, result = size_case(setup)
write_case_plots(prob, setup, "results/crm")
print(f"CRM: mass {result['mass_kg']:.0f} kg, KS {result['ks']}, {result['wall_s']:.1f} s")
