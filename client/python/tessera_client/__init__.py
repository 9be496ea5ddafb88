"""Python client for tessera-server (client/python/README.md)."""
from tessera_client.canonical import canonical_sha256
from tessera_client.client import (Camera, Frame, IntegrityError, InvalidArgumentError, Tessellation, TesseraClient,
                                   TesseraError, mesh_id)

__all__ = ["Camera", "Frame", "IntegrityError", "InvalidArgumentError", "Tessellation", "TesseraClient",
           "TesseraError", "canonical_sha256", "mesh_id"]
