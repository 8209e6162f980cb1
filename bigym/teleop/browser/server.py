"""The browser front end: a small local web server with one WebSocket.

``GET /`` serves the page (``static/``); ``/ws`` is a WebSocket on which the page sends
raw device events as JSON text (keyboard, mouse, Gamepad API, WebXR controllers, and the
page's keep / discard / retry buttons) and receives the views as binary JPEG frames
(first byte: the view, 0 scene, 1 head camera) and the session's status as JSON text.

The simulation runs on a thread of its own in real time: each frame it takes the events
that arrived, advances the session by the wall-clock time that passed, and at
``frame_rate`` renders the views. The asyncio loop only moves messages, so the page
stays responsive while a demo is verified. Serve on ``127.0.0.1`` (the default) and use
SSH port forwarding to reach a remote machine; WebXR needs a secure context, which
``localhost`` is.
"""

from __future__ import annotations

import asyncio
import io
import json
import mimetypes
import queue
import threading
import time
from importlib import resources

import numpy as np

from bigym.teleop.devices import DeviceEventError
from bigym.teleop.devices.keyboard import KEY_HELP

#: the views sent to the page: (byte that tags the frame, camera, resolution (h, w))
VIEWS = ((0, "external", (360, 480)), (1, "head", (240, 320)))
MAX_CATCH_UP = 125  # control steps (0.25 s) one round may catch up on
STATIC = "static"


def encode_jpeg(rgb: np.ndarray, quality: int = 80) -> bytes:
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(rgb).save(buffer, "JPEG", quality=quality)
    return buffer.getvalue()


class ViewRenderer:
    """Renders the page's views of a session's env (on the simulation thread)."""

    def __init__(self, env) -> None:
        from bigym.observations import CameraConfig
        from bigym.rendering import CameraRenderer

        self.env = env
        self.renderers = [
            (tag, name, CameraRenderer(env.model, [CameraConfig(name, resolution=size)], skybox=name == "external"))
            for tag, name, size in VIEWS
        ]

    def frames(self) -> list[bytes]:
        self.env.robot.pose_legs(self.env.model, self.env.data)
        frames = []
        for tag, name, renderer in self.renderers:
            out: dict[str, np.ndarray] = {}
            renderer.render(self.env.data, out)
            frames.append(bytes([tag]) + encode_jpeg(out[f"rgb_{name}"].transpose(1, 2, 0)))
        return frames

    def close(self) -> None:
        for _, _, renderer in self.renderers:
            renderer.close()


class TeleopServer:
    """Serves one :class:`~bigym.teleop.session.TeleopSession` to any number of pages."""

    def __init__(self, session, host: str = "127.0.0.1", port: int = 8765, frame_rate: float = 15.0) -> None:
        self.session = session
        self.host, self.port = host, port
        self.frame_rate = frame_rate
        self.inputs: queue.SimpleQueue = queue.SimpleQueue()
        self.clients: set = set()
        self.frames_sent = 0
        self._stop = threading.Event()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._started = threading.Event()
        self._error: BaseException | None = None

    @property
    def url(self) -> str:
        return f"http://{self.host}:{self.port}/"

    # ------------------------------------------------------------------ simulation thread
    def simulate(self) -> None:
        """Real-time loop: events in, steps, frames and status out (until stopped)."""
        views = ViewRenderer(self.session.env)
        try:
            start, done, next_frame = time.perf_counter(), 0, 0.0
            rate = self.session.env.control_frequency
            while not self._stop.is_set():
                now = time.perf_counter() - start
                errors = []
                while not self.inputs.empty():
                    try:
                        self.session.handle(self.inputs.get())
                    except DeviceEventError as error:
                        errors.append(str(error))
                due = int(now * rate) - done
                steps = min(max(due, 0), MAX_CATCH_UP)
                outcomes = self.session.advance(steps)
                done += steps if due <= MAX_CATCH_UP else due  # a stall (verifying a demo) is not caught up
                status = {"type": "status", **self.session.status.to_dict(),
                          "outcomes": [o.describe() for o in outcomes], "errors": errors}  # fmt: skip
                if now >= next_frame or outcomes or errors:
                    next_frame = now + 1.0 / self.frame_rate
                    self._publish(views.frames(), json.dumps(status))
                time.sleep(max(0.0, 1.0 / 250.0 - (time.perf_counter() - start - now)))
        finally:
            views.close()

    def _publish(self, frames: list[bytes], status: str) -> None:
        if self._loop is not None and not self._loop.is_closed():
            self._loop.call_soon_threadsafe(self._broadcast, [*frames, status])

    def _broadcast(self, messages: list) -> None:
        from websockets.asyncio.server import broadcast

        for message in messages:
            broadcast(self.clients, message)
        self.frames_sent += 1

    # ------------------------------------------------------------------ web
    def _hello(self) -> str:
        session = self.session
        return json.dumps({"type": "hello", "task": session.task, "devices": [d.name for d in session.devices],
                           "keys": KEY_HELP, "views": [name for _, name, _ in VIEWS]})  # fmt: skip

    async def _client(self, connection) -> None:
        from websockets.exceptions import ConnectionClosed

        self.clients.add(connection)
        try:
            await connection.send(self._hello())
            async for message in connection:
                try:
                    event = json.loads(message)
                except (json.JSONDecodeError, TypeError):
                    await connection.send(json.dumps({"type": "error", "message": f"not JSON: {message!r:.80}"}))
                    continue
                self.inputs.put(event)
        except ConnectionClosed:  # a page closing mid-message is not the server's problem
            pass
        finally:
            self.clients.discard(connection)

    def _http(self, connection, request):
        """Static files for every path but the WebSocket's."""
        from websockets.datastructures import Headers
        from websockets.http11 import Response

        path = request.path.split("?")[0]
        if path == "/ws":
            return None
        name = "index.html" if path == "/" else path.lstrip("/")
        folder = resources.files("bigym.teleop.browser") / STATIC
        file = folder / name
        if "/" in name or ".." in name or not file.is_file():
            return connection.respond(404, "not found\n")
        body = file.read_bytes()
        kind = mimetypes.guess_type(name)[0] or "application/octet-stream"
        headers = Headers([("Content-Type", kind), ("Content-Length", str(len(body))), ("Cache-Control", "no-store")])
        return Response(200, "OK", headers, body)

    async def _serve(self) -> None:
        from websockets.asyncio.server import serve

        self._loop = asyncio.get_running_loop()
        async with serve(self._client, self.host, self.port, process_request=self._http, max_size=2**20) as server:
            self.port = server.sockets[0].getsockname()[1]  # port 0: the one the system chose
            simulation = threading.Thread(target=self._simulate_safely, name="bigym-teleop-sim", daemon=True)
            simulation.start()
            self._started.set()
            while not self._stop.is_set():
                await asyncio.sleep(0.05)
            simulation.join()

    def _simulate_safely(self) -> None:
        try:
            self.simulate()
        except BaseException as error:  # noqa: BLE001 - reported to the caller
            self._error = error
            self._stop.set()

    def serve_forever(self) -> None:
        """Serve until interrupted (Ctrl-C) or :meth:`stop`."""
        try:
            asyncio.run(self._serve())
        except KeyboardInterrupt:
            self._stop.set()
        if self._error is not None:
            raise self._error

    def start(self) -> str:
        """Serve on a background thread; returns the page's URL once it is up."""
        thread = threading.Thread(target=self.serve_forever, name="bigym-teleop-web", daemon=True)
        thread.start()
        if not self._started.wait(timeout=60):
            raise RuntimeError(f"the teleop server did not start: {self._error!r}")
        self._thread = thread
        return self.url

    def wait(self) -> None:
        """Block until the server stops; re-raise what stopped its simulation, if anything."""
        while self._thread.is_alive():
            self._thread.join(timeout=0.2)
        if self._error is not None:
            raise self._error

    def stop(self) -> None:
        self._stop.set()
        thread = getattr(self, "_thread", None)
        if thread is not None:
            thread.join(timeout=30)


__all__ = ["VIEWS", "TeleopServer"]
