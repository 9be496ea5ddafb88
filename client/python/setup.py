"""Builds tessera-client with its gRPC stubs generated from the repository's proto/ files.

The stubs are made at build time with the system protoc and grpc_python_plugin (Debian's
python3-grpc-tools bundles protoc 3.5, which refuses proto3 `optional`). protoc names the modules
after the proto paths (tessera.v1.mesh_pb2, grpc.health.v1.health_pb2); they are placed under
tessera_client._proto and their imports of one another rewritten to match, so they cannot clash
with grpcio's own `grpc` package.

setuptools' scratch folders (build/, tessera_client.egg-info) go to a temporary directory removed
when the build ends, not into the checkout `pip install client/python` is run from.
"""
import atexit
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

from setuptools import setup
from setuptools.command.build import build
from setuptools.command.build_py import build_py
from setuptools.command.egg_info import egg_info

HERE = Path(__file__).resolve().parent
PROTO_ROOT = Path(os.environ.get("TESSERA_PROTO_DIR", HERE.parent.parent / "proto"))
PROTOS = [
    "tessera/v1/geometry.proto",
    "tessera/v1/mesh.proto",
    "tessera/v1/tessellation.proto",
    "tessera/v1/render.proto",
    "tessera/v1/server_info.proto",
    "grpc/health/v1/health.proto",
]
PACKAGE = "tessera_client._proto"
SERVICE_CONFIG = "tessera/v1/service_config.json"
# `from tessera.v1 import mesh_pb2 as ...` and `from grpc.health.v1 import ...` in generated code.
IMPORT = re.compile(r"^from (tessera\.v1|grpc\.health\.v1) import ", re.MULTILINE)


def generate_stubs(out_dir: Path) -> None:
    protoc = shutil.which("protoc")
    plugin = shutil.which("grpc_python_plugin")
    if not protoc or not plugin:
        raise RuntimeError("tessera-client needs protoc and grpc_python_plugin "
                           "(Debian: protobuf-compiler, protobuf-compiler-grpc)")
    for proto in PROTOS:
        if not (PROTO_ROOT / proto).is_file():
            raise RuntimeError(f"tessera-client: {PROTO_ROOT / proto} not found (set TESSERA_PROTO_DIR)")
    target = out_dir / "tessera_client" / "_proto"
    shutil.rmtree(target, ignore_errors=True)
    target.mkdir(parents=True)
    subprocess.run([protoc, f"-I{PROTO_ROOT}", f"--python_out={target}", f"--grpc_python_out={target}",
                    f"--plugin=protoc-gen-grpc_python={plugin}", *PROTOS], check=True)
    for path in target.rglob("*.py"):
        text = path.read_text()
        path.write_text(IMPORT.sub(lambda m: f"from {PACKAGE}.{m.group(1)} import ", text))
    for directory in [target, *[d for d in target.rglob("*") if d.is_dir()]]:
        (directory / "__init__.py").touch()
    # The API's client service config (round_robin over healthy servers, retries of UNAVAILABLE).
    shutil.copyfile(PROTO_ROOT / SERVICE_CONFIG, target / "service_config.json")


class BuildWithStubs(build_py):
    def run(self):
        super().run()
        generate_stubs(Path(self.build_lib))


def _scratch() -> str:
    """One temporary folder per build process, removed when it exits."""
    global _SCRATCH
    if _SCRATCH is None:
        _SCRATCH = tempfile.mkdtemp(prefix="tessera-client-build-")
        atexit.register(shutil.rmtree, _SCRATCH, True)
    return _SCRATCH


_SCRATCH = None


class BuildOutOfTree(build):
    """build/ (and bdist's folders under it) in the scratch folder; --build-base still wins."""

    def initialize_options(self):
        super().initialize_options()
        self.build_base = os.path.join(_scratch(), "build")


class EggInfoOutOfTree(egg_info):
    """The egg-info pip's wheel build writes, in the scratch folder; --egg-base still wins."""

    def initialize_options(self):
        super().initialize_options()
        self.egg_base = _scratch()


setup(cmdclass={"build_py": BuildWithStubs, "build": BuildOutOfTree, "egg_info": EggInfoOutOfTree})
