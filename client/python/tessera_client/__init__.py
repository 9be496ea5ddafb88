"""Python client for tessera-server (client/python/README.md)."""
from tessera_client.canonical import canonical_sha256
from tessera_client.client import (Camera, Frame, IntegrityError, Tessellation, TesseraClient, TesseraError)

__all__ = ["Camera", "Frame", "IntegrityError", "Tessellation", "TesseraClient", "TesseraError", "canonical_sha256"]
