"""Resident memory of a fresh tessera-server around one large RAW_RGBA frame of bigguy
(bench/MEMORY-RESULTS.md, issue 47 item 3): VmRSS after a 64 x 64 frame (the device, its
pipelines and bigguy's patch set: the resting server), after the large frame, 5 s later, and the
peak. Usage, with the Python client installed (tests/python/install-client.sh . build/python-client):
  build/python-client/venv/bin/python bench/frame_memory.py build/server/tessera-server ../shared/models 8192"""
import subprocess, sys, tempfile, time
from pathlib import Path
from tessera_client import Camera, TesseraClient

server_binary, models, side = sys.argv[1], Path(sys.argv[2]), int(sys.argv[3])

def status(pid, key):
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith(key + ":"):
            return int(line.split()[1]) / 1024.0
scratch = tempfile.mkdtemp()
ready = Path(scratch) / "ready"
server = subprocess.Popen([server_binary, "--listen", "127.0.0.1:0", "--store", f"sqlite:{scratch}/t.db", "--metrics-listen", "off",
                           "--ready-file", str(ready), "--log-level", "warn"])
while not ready.exists():
    time.sleep(0.05)
address = ready.read_text().split("grpc=")[1].split()[0]
try:
    with TesseraClient(address) as client:
        print(f"fresh server: VmRSS {status(server.pid, 'VmRSS'):.0f} MiB")
        client.upload_obj("bigguy", models / "bigguy.obj")
        # Looking at the centre of bigguy's box from 47 units in front: it fills the frame.
        camera = lambda w, h: Camera(eye=(0.535, 1.055, 0.075 + 47.0), target=(0.535, 1.055, 0.075), fov_y_deg=40, width=w, height=h)
        client.render("bigguy", [camera(64, 64)], image_format="raw_rgba", timeout=600)
        rest = status(server.pid, "VmRSS")
        print(f"after a 64 x 64 frame (device, pipelines, patch set): VmRSS {rest:.0f} MiB")
        start = time.monotonic()
        frames = client.render("bigguy", [camera(side, side)], image_format="raw_rgba", timeout=600)
        took = time.monotonic() - start
        h = frames[0].header
        print(f"{side} x {side} RAW frame: {len(frames[0].image)} bytes in {took:.1f} s "
              f"(plan {h.timings.plan_ms:.0f} ms, tessellation {h.timings.tessellation_ms:.0f}, raster {h.timings.raster_shading_ms:.0f}, "
              f"crack filling {h.timings.crack_filling_ms:.0f}, render {h.timings.render_ms:.0f}, encode {h.timings.encode_ms:.0f}; "
              f"{h.statistics.triangles} triangles)")
        del frames
        after = status(server.pid, "VmRSS")
        time.sleep(5)
        later = status(server.pid, "VmRSS")
        print(f"after it: VmRSS {after:.0f} MiB, 5 s later {later:.0f} MiB, peak VmHWM {status(server.pid, 'VmHWM'):.0f} MiB; "
              f"{after - rest:+.0f} MiB over the resting server")
finally:
    server.terminate(); server.wait()
