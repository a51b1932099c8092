"""uCRM multipoint aerostructural fuel-burn problem with the wingmdao beam beside OpenAeroStruct's own.

The problem (OpenAeroStruct's wingbox multipoint example with our beam and our KS stress
constraint) is built by :mod:`wingmdao.oas.crm`; ``wingmdao size aerostruct-crm`` runs the same
problem with recordings, output checks and Ctrl-C handling (docs/embedding.md).

    python cases/run_aerostruct_crm.py --analysis-only --json -     # one coupled analysis, both beams
    python cases/run_aerostruct_crm.py --json result.json            # optimise with both beams
"""

from __future__ import annotations

import argparse
import json
import sys


def main(argv=None):
    from wingmdao.cli._io import write_json
    from wingmdao.oas.crm import run_crm

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    ap.add_argument("--analysis-only", action="store_true", help="one coupled analysis of the initial design")
    ap.add_argument("--json", metavar="FILE", help="write the results as JSON ('-' for stdout)")
    ap.add_argument("--maxiter", type=int, default=40, help="SLSQP iterations (optimisation)")
    ap.add_argument("--tol", type=float, default=1e-6, help="SLSQP tolerance")
    ap.add_argument("--num-y", type=int, default=15, help="spanwise mesh points of the full wing (odd, >= 9)")
    a = ap.parse_args(argv)
    kw = dict(analysis_only=a.analysis_only, maxiter=a.maxiter, tol=a.tol, num_y=a.num_y)
    res = run_crm("wingmdao", **kw)
    res["oas_beam"] = run_crm("oas", **kw)
    if a.json:
        write_json(res, a.json)
    if a.json != "-":
        print(json.dumps({k: v for k, v in res.items() if not isinstance(v, (list, dict)) or k == "ks"}, indent=2),
              file=sys.stderr)
    return res


if __name__ == "__main__":
    main()
