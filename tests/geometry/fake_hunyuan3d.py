"""A local stand-in for Tencent Hunyuan3D-2's api_server.py: the same endpoints and body shapes, no model inside.

Endpoints as in github.com/Tencent/Hunyuan3D-2 api_server.py (commit 2ee477019f15cabc4a9546b1ed9bb21862136bdf):
POST /generate (JSON with "image" base64 or "text", "seed", options) -> 200 with the GLB file as the body, or 404
with {"text": ..., "error_code": 1}; POST /send -> {"uid"}; GET /status/{uid} -> {"status": "processing"} or
{"status": "completed", "model_base64"}. Like the real server, a text-only request fails unless text-to-image is on,
and a job that fails in /send's thread stays "processing". `behaviour` adds the ways a server can misbehave.
"""

from __future__ import annotations

import base64
import io
import json
import threading
import time
import uuid
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any

import trimesh
from PIL import Image

SERVER_ERROR_MSG = "**NETWORK ERROR DUE TO HIGH TRAFFIC. PLEASE REGENERATE OR REFRESH THIS PAGE.**"


def glb_shape() -> bytes:
    """A normalised, y-up GLB scene as the model returns it: a 0.6 x 1.0 x 0.4 ellipsoid (y tallest)."""
    body = trimesh.creation.icosphere(subdivisions=3, radius=0.5)
    body.apply_scale([0.6, 1.0, 0.4])
    return bytes(trimesh.Scene([body]).export(file_type="glb"))


class FakeHunyuan3D:
    """`with FakeHunyuan3D() as srv:` serves on 127.0.0.1, a free port; `srv.url`, `srv.bodies` (JSON received)."""

    def __init__(self, behaviour: str = "ok", delay_s: float = 0.0, text_to_image: bool = False) -> None:
        self.behaviour = behaviour   # ok | crash (500) | garbage (200, HTML) | slow (/generate sleeps 2 s)
        self.delay_s = delay_s       # how long a /send job takes
        self.text_to_image = text_to_image
        self.bodies: list[dict[str, Any]] = []
        self.polls = 0
        self.jobs: dict[str, bytes | None] = {}
        self._httpd = ThreadingHTTPServer(("127.0.0.1", 0), self._handler())
        self._httpd.daemon_threads, self._httpd.block_on_close = True, False  # close without waiting for 'slow'
        self.url = f"http://127.0.0.1:{self._httpd.server_address[1]}"

    def __enter__(self) -> FakeHunyuan3D:
        threading.Thread(target=self._httpd.serve_forever, daemon=True).start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._httpd.shutdown()
        self._httpd.server_close()

    def generate(self, params: dict[str, Any]) -> bytes:
        """ModelWorker.generate: an image (base64, any format PIL reads) or, when enabled, text; else ValueError."""
        if "image" in params:
            Image.open(io.BytesIO(base64.b64decode(params["image"]))).load()
        elif "text" not in params or not self.text_to_image:
            raise ValueError("No input image or text provided" if "text" not in params else "no text-to-image")
        int(params.get("seed", 1234))
        return glb_shape()

    def _handler(self) -> type[BaseHTTPRequestHandler]:
        fake = self

        class Handler(BaseHTTPRequestHandler):
            def do_POST(self) -> None:  # noqa: N802 - http.server's name
                params = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
                fake.bodies.append(params)
                if self.path == "/generate":
                    self._generate(params)
                elif self.path == "/send":
                    uid = str(uuid.uuid4())
                    fake.jobs[uid] = None
                    threading.Thread(target=self._job, args=(uid, params), daemon=True).start()
                    self._json(200, {"uid": uid})
                else:
                    self._json(404, {"detail": "Not Found"})

            def do_GET(self) -> None:  # noqa: N802
                if not self.path.startswith("/status/"):
                    self._json(404, {"detail": "Not Found"})
                    return
                fake.polls += 1
                if fake.behaviour == "garbage":
                    self._send(200, b"<html>model is loading</html>", "text/html")
                    return
                glb = fake.jobs.get(self.path.removeprefix("/status/"))
                if glb is None:
                    self._json(200, {"status": "processing"})
                else:
                    self._json(200, {"status": "completed", "model_base64": base64.b64encode(glb).decode()})

            def _job(self, uid: str, params: dict[str, Any]) -> None:
                time.sleep(fake.delay_s)
                try:
                    fake.jobs[uid] = fake.generate(params)
                except Exception:  # noqa: BLE001 - as the real server: the job stays 'processing'
                    pass

            def _generate(self, params: dict[str, Any]) -> None:
                if fake.behaviour == "crash":
                    self._send(500, b"Internal Server Error", "text/plain")
                elif fake.behaviour == "garbage":
                    self._send(200, b"<html>model is loading</html>", "text/html")
                elif fake.behaviour == "slow":
                    time.sleep(2.0)
                    self._send(200, glb_shape(), "model/gltf-binary")
                else:
                    try:
                        glb = fake.generate(params)
                    except Exception:  # noqa: BLE001 - api_server.py answers every failure so
                        self._json(404, {"text": SERVER_ERROR_MSG, "error_code": 1})
                        return
                    self._send(200, glb, "model/gltf-binary")

            def _json(self, code: int, obj: dict[str, Any]) -> None:
                self._send(code, json.dumps(obj).encode(), "application/json")

            def _send(self, code: int, data: bytes, ctype: str) -> None:
                try:
                    self.send_response(code)
                    self.send_header("Content-Type", ctype)
                    self.send_header("Content-Length", str(len(data)))
                    self.end_headers()
                    self.wfile.write(data)
                except (BrokenPipeError, ConnectionResetError):  # the client gave up (timeout test)
                    pass

            def log_message(self, *args: object) -> None:
                """Silent."""

        return Handler
