"""sweepd_client: the Python client of sweepd (see client.py for the API).

    from sweepd_client import Client
    with Client("127.0.0.1", 7878, token="SECRET") as sweepd:
        posed = sweepd.pose("mannequin")          # the rest pose; .positions is (n, 3) float32
"""

from .client import Client, Clip, MeshRange, Model, ModelSummary, Posed, RestMesh
from .errors import ConnectionLost, ServerError, SweepdError, Timeout
from .meshopt import MeshoptUnavailable

__all__ = ["Client", "Clip", "MeshRange", "Model", "ModelSummary", "Posed", "RestMesh", "SweepdError",
           "ConnectionLost", "Timeout", "ServerError", "MeshoptUnavailable"]
