"""sweepd_client: the Python client of sweepd (see exchanges.py for the requests).

    from sweepd_client import Client
    with Client("127.0.0.1", 7878, token="SECRET") as sweepd:
        posed = sweepd.pose("mannequin")          # the rest pose; .positions is (n, 3) float32

    from sweepd_client import AsyncClient         # the same requests under asyncio
    async with AsyncClient("127.0.0.1", 7878, token="SECRET") as sweepd:
        posed = await sweepd.pose("mannequin")
"""

from .async_client import AsyncClient
from .client import Client
from .errors import ConnectionLost, ServerError, SweepdError, Timeout
from .exchanges import BindWarning, Clip, MeshRange, Model, ModelSummary, Posed, RestMesh, Sheet
from .meshopt import MeshoptUnavailable

__all__ = ["Client", "AsyncClient", "BindWarning", "Clip", "MeshRange", "Model", "ModelSummary", "Posed", "RestMesh", "Sheet",
           "SweepdError", "ConnectionLost", "Timeout", "ServerError", "MeshoptUnavailable"]
