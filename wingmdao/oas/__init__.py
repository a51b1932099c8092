"""OpenAeroStruct coupling: the wingmdao beam in place of OpenAeroStruct's spatial beam.

See :mod:`wingmdao.oas.coupling` and docs/embedding.md. The components here use only numpy and
OpenMDAO; OpenAeroStruct itself is needed only to build the aerodynamic side.
"""

from wingmdao.oas.coupling import (BeamToOASDisp, OASBeamStates, OASThicknessToBox, OASToBeamLoads,
                                   oas_order)

__all__ = ["OASToBeamLoads", "BeamToOASDisp", "OASThicknessToBox", "OASBeamStates", "oas_order"]
