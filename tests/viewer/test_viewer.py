"""`candela view` driven by Debian's Chromium headless (Selenium): the page shows the scene and
agrees with `candela render`, its controls do what they say, and the server is safe (token,
traversal, hostile messages, many pages). Run with Debian's python3:

    /usr/bin/python3 -m pytest -s tests/viewer

CANDELA_BINARY names the candela to test (default build/candela). CANDELA_VIEWER_SCREENSHOTS=1
also writes docs/images/viewer-split.png and viewer-heatmap.png. The measurement run
(test_measurements, run when CANDELA_VIEWER_BENCH=1) prints the frame rate, latency and
samples/s figures and writes them to bench/results/viewer_<date>.txt; it asserts only that it
could measure them, never a speed.

Every process the tests start (the servers, chromedriver and its browser) is stopped by a
fixture's finalizer, also when a test fails.
"""

from __future__ import annotations

import base64
import datetime
import hashlib
import http.client
import json
import math
import os
import platform
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.request
import zlib
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("CANDELA_BINARY", str(REPO / "build" / "candela")))
SCENE = REPO / "scenes" / "validation" / "cbox.xml"
ASSETS = REPO / "viewer" / "assets"
CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"
SCREENSHOTS = os.environ.get("CANDELA_VIEWER_SCREENSHOTS") == "1"

# The functional tests' scene: the validation Cornell box at 64 x 64; the path side converges to
# 256 spp (1M samples: about a second on 2 cores).
RES = 64
SPP = 256

try:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.actions.wheel_input import ScrollOrigin
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import Select
    HAVE_SELENIUM = True
except ImportError:  # pragma: no cover - reported by the skip below
    HAVE_SELENIUM = False

pytestmark = [
    pytest.mark.skipif(not BINARY.exists(), reason=f"{BINARY} is not built (CANDELA_BINARY)"),
]
needs_browser = pytest.mark.skipif(
    not (HAVE_SELENIUM and os.path.exists(CHROMIUM) and os.path.exists(CHROMEDRIVER)),
    reason="needs Debian's chromium, chromium-driver and python3-selenium (scripts/install-deps.sh)")


# ------------------------------------------------------------------------------------------------
# Waiting (for conditions, never for speed)

def wait_until(condition, timeout, what):
    """Polls condition() until it returns something true; fails naming `what` after timeout s."""
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}")
        time.sleep(0.05)


# ------------------------------------------------------------------------------------------------
# Processes: every one started here is in its own process group, and ended with it

def kill_group(process: subprocess.Popen, grace: float = 5.0):
    if process.poll() is not None:
        return
    try:
        os.killpg(process.pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    try:
        process.wait(grace)
    except subprocess.TimeoutExpired:
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        process.wait(grace)


class ViewServer:
    """`candela view SCENE --port 0 ...` in its own process group; url/port/token from its output."""

    def __init__(self, res=RES, spp=SPP, extra=()):
        self.log = tempfile.NamedTemporaryFile(prefix="candela-view-", suffix=".log", delete=False)
        self.process = subprocess.Popen(
            [str(BINARY), "view", str(SCENE), "--port", "0", "-D", f"res={res}", "-D", f"spp={spp}", *extra],
            stdout=subprocess.PIPE, stderr=self.log, stdin=subprocess.DEVNULL, start_new_session=True, text=True)
        self.lines = []
        found = threading.Event()

        def read():
            for line in self.process.stdout:
                self.lines.append(line)
                if re.search(r"http://127\.0\.0\.1:\d+/\?token=\S+", line):
                    found.set()
            found.set()

        threading.Thread(target=read, daemon=True).start()
        if not found.wait(60) or not any("token=" in l for l in self.lines):
            self.stop()
            raise AssertionError(f"candela view printed no URL: {''.join(self.lines)!r}, stderr: {self.stderr()!r}")
        match = next(m for m in (re.search(r"(http://127\.0\.0\.1:(\d+)/\?token=([A-Za-z0-9_\-]+))", l) for l in self.lines) if m)
        self.url, self.port, self.token = match.group(1), int(match.group(2)), match.group(3)
        self.base = f"http://127.0.0.1:{self.port}"

    def hello(self) -> dict:
        """The scene message a new page gets (the current camera and settings)."""
        with WebSocket(self.port, self.token) as ws:
            assert ws.status == 101, ws.response
            ws.send_json({"type": "hello"})
            return ws.receive_json("scene", 30)

    def stderr(self) -> str:
        try:
            return Path(self.log.name).read_text(errors="replace")
        except OSError:
            return ""

    def alive(self) -> bool:
        return self.process.poll() is None

    def stop(self):
        kill_group(self.process)
        self.log.close()
        try:
            os.unlink(self.log.name)
        except OSError:
            pass


@pytest.fixture(scope="module")
def server(request):
    s = ViewServer()
    request.addfinalizer(s.stop)
    # The state every test starts from: the scene's camera and the server's initial settings.
    s.initial = s.hello()
    return s


# ------------------------------------------------------------------------------------------------
# A minimal WebSocket client (RFC 6455) on the standard library, for raw and hostile messages

class WebSocket:
    def __init__(self, port, token=None, path="/ws", timeout=10.0):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=timeout)
        key = base64.b64encode(os.urandom(16)).decode()
        query = "" if token is None else f"?token={token}"
        self.sock.sendall((f"GET {path}{query} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n"
                           f"Origin: http://127.0.0.1:{port}\r\n\r\n").encode())
        self.buffer = b""
        while b"\r\n\r\n" not in self.buffer:
            try:
                chunk = self.sock.recv(4096)
            except (socket.timeout, ConnectionError):
                chunk = b""
            if not chunk:
                break
            self.buffer += chunk
        head, _, self.buffer = self.buffer.partition(b"\r\n\r\n")
        self.response = head.decode("latin-1")
        status = re.match(r"HTTP/1\.[01] (\d{3})", self.response)
        self.status = int(status.group(1)) if status else None
        if self.status == 101:
            expected = base64.b64encode(hashlib.sha1((key + "258EAFA5-E914-47DA-95CA-C5AB0DC85B11").encode()).digest()).decode()
            assert f"sec-websocket-accept: {expected}".lower() in self.response.lower()
        self.frames = 0
        self.texts = []

    def __enter__(self):
        return self

    def __exit__(self, *args):
        self.close()

    def close(self):
        try:
            self.send(b"\x03\xe8", opcode=8)
        except OSError:
            pass
        self.sock.close()

    def send(self, payload: bytes, opcode=1):
        mask = os.urandom(4)
        n = len(payload)
        if n < 126:
            head = struct.pack("!BB", 0x80 | opcode, 0x80 | n)
        elif n < 65536:
            head = struct.pack("!BBH", 0x80 | opcode, 0x80 | 126, n)
        else:
            head = struct.pack("!BBQ", 0x80 | opcode, 0x80 | 127, n)
        masked = bytes(b ^ mask[i % 4] for i, b in enumerate(payload)) if n < 65536 else \
            (np.frombuffer(payload, np.uint8) ^ np.resize(np.frombuffer(mask, np.uint8), n)).tobytes()
        self.sock.sendall(head + mask + masked)

    def send_text(self, text: str):
        self.send(text.encode())

    def send_json(self, message):
        self.send_text(json.dumps(message))

    def _read(self, n, deadline):
        while len(self.buffer) < n:
            self.sock.settimeout(max(0.01, deadline - time.monotonic()))
            chunk = self.sock.recv(1 << 16)
            if not chunk:
                raise EOFError("the server closed the connection")
            self.buffer += chunk
        data, self.buffer = self.buffer[:n], self.buffer[n:]
        return data

    def receive(self, timeout=10.0):
        """The next message: (opcode, payload); answers pings."""
        deadline = time.monotonic() + timeout
        message, message_opcode = b"", None
        while True:
            b0, b1 = self._read(2, deadline)
            opcode, n = b0 & 0x0F, b1 & 0x7F
            if n == 126:
                n = struct.unpack("!H", self._read(2, deadline))[0]
            elif n == 127:
                n = struct.unpack("!Q", self._read(8, deadline))[0]
            mask = self._read(4, deadline) if b1 & 0x80 else None
            payload = self._read(n, deadline)
            if mask:
                payload = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
            if opcode == 9:
                self.send(payload, opcode=10)
                continue
            if opcode == 10:
                continue
            if opcode == 8:
                raise EOFError(f"the server closed the WebSocket: {payload!r}")
            if opcode != 0:
                message_opcode = opcode
            message += payload
            if b0 & 0x80:
                if message_opcode == 2:
                    self.frames += 1
                return message_opcode, message

    def receive_json(self, wanted, timeout=10.0):
        """The next text message of type `wanted` (a string or a tuple), skipping frames and others."""
        deadline = time.monotonic() + timeout
        wanted = (wanted,) if isinstance(wanted, str) else wanted
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise AssertionError(f"no {wanted} message within {timeout} s")
            try:
                opcode, payload = self.receive(remaining)
            except socket.timeout:
                raise AssertionError(f"no {wanted} message within {timeout} s")
            if opcode == 1:
                message = json.loads(payload)
                self.texts.append(message)
                if message.get("type") in wanted:
                    return message


# ------------------------------------------------------------------------------------------------
# Images: PNG (what `candela render --png` writes) and EXR headers, read with the standard library

def read_png(path) -> np.ndarray:
    """An 8-bit RGB or RGBA, non-interlaced PNG as H x W x 3 uint8."""
    data = Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack("!I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            header = struct.unpack("!IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    width, height, depth, colour, _, _, interlace = header
    assert depth == 8 and colour in (2, 6) and interlace == 0, header
    channels = 3 if colour == 2 else 4
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(height, 1 + width * channels)
    out = np.zeros((height, width * channels), np.int32)
    for y in range(height):
        kind, line = raw[y, 0], raw[y, 1:].astype(np.int32)
        previous = out[y - 1] if y else np.zeros(width * channels, np.int32)
        if kind == 0:
            row = line
        elif kind == 2:
            row = (line + previous) & 0xFF
        else:
            row = np.zeros_like(line)
            for i in range(len(line)):
                left = row[i - channels] if i >= channels else 0
                up, corner = previous[i], (previous[i - channels] if i >= channels else 0)
                if kind == 1:
                    predictor = left
                elif kind == 3:
                    predictor = (left + up) // 2
                else:
                    p = left + up - corner
                    pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                    predictor = left if pa <= pb and pa <= pc else (up if pb <= pc else corner)
                row[i] = (line[i] + predictor) & 0xFF
        out[y] = row
    return out.reshape(height, width, channels)[:, :, :3].astype(np.uint8)


# OpenEXR's magic number: the bytes 0x76 0x2f 0x31 0x01 (20000630 as a little-endian integer).
EXR_MAGIC = b"\x76\x2f\x31\x01"


def exr_header(data: bytes) -> dict:
    """The attributes of a scanline OpenEXR file's header: channels (names) and dataWindow."""
    assert data[:4] == EXR_MAGIC, "not an OpenEXR file (magic number)"
    pos, attributes = 8, {}
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        name, kind = data[pos:name_end].decode(), data[name_end + 1:type_end].decode()
        size = struct.unpack("<i", data[type_end + 1:type_end + 5])[0]
        value = data[type_end + 5:type_end + 5 + size]
        if kind == "chlist":
            names, p = [], 0
            while value[p] != 0:
                end = value.index(b"\0", p)
                names.append(value[p:end].decode())
                p = end + 1 + 16
            attributes[name] = names
        elif kind == "box2i":
            attributes[name] = struct.unpack("<4i", value)
        else:
            attributes[name] = (kind, value)
        pos = type_end + 5 + size
    return attributes


def cli_render(tmp: Path, name: str, *args, res=RES, spp=SPP) -> tuple[np.ndarray, str]:
    """`candela render` of the test scene as 8-bit sRGB (exposure 0, clamped: `--png`), and its
    summary line."""
    out = tmp / f"{name}.exr"
    done = subprocess.run([str(BINARY), "render", str(SCENE), "-D", f"res={res}", "-D", f"spp={spp}", "-o", str(out), "--png", *args],
                          capture_output=True, text=True, timeout=600, start_new_session=True)
    assert done.returncode == 0, done.stderr
    # The render's summary ("wrote X.exr: ... samples/s ..."), not the --png line after it.
    summary = [l for l in (done.stdout + done.stderr).splitlines() if l.startswith("wrote") and "samples/s" in l]
    return read_png(out.with_suffix(".png")), (summary[-1] if summary else "")


def mad(a: np.ndarray, b: np.ndarray) -> float:
    """Mean absolute difference of 8-bit values."""
    return float(np.mean(np.abs(a.astype(np.float64) - b.astype(np.float64))))


# ------------------------------------------------------------------------------------------------
# The browser

def chrome_options(download_dir=None):
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--disable-quic",
                     "--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync",
                     "--disable-default-apps", "--disable-extensions", "--window-size=1280,900",
                     f"--user-data-dir={tempfile.mkdtemp(prefix='candela-chromium-')}"):
        options.add_argument(argument)
    if download_dir:
        options.add_experimental_option("prefs", {"download.default_directory": str(download_dir),
                                                  "download.prompt_for_download": False})
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return options


def descendants(pid: int) -> list[int]:
    """The processes below pid (from /proc), children first."""
    children = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = Path(f"/proc/{entry}/stat").read_text()
                parent = int(stat[stat.rindex(")") + 2:].split()[1])
            except (OSError, ValueError, IndexError):
                continue
            children.setdefault(parent, []).append(int(entry))
    out, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            out.append(child)
            todo.append(child)
    return out


class Browser:
    """chromedriver + headless Chromium; quit() ends both and anything left of them."""

    def __init__(self):
        self.downloads = Path(tempfile.mkdtemp(prefix="candela-downloads-"))
        options = chrome_options(self.downloads)
        self.user_data = next(a.split("=", 1)[1] for a in options.arguments if a.startswith("--user-data-dir="))
        self.service = Service(CHROMEDRIVER)
        self.driver = webdriver.Chrome(service=self.service, options=options)
        self.driver.set_script_timeout(60)
        self.driver.execute_cdp_cmd("Page.setDownloadBehavior", {"behavior": "allow", "downloadPath": str(self.downloads)})

    def quit(self):
        process = getattr(self.service, "process", None)
        started = descendants(process.pid) if process else []
        try:
            self.driver.quit()
        finally:
            for pid in started:  # only processes this browser started
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            if process and process.poll() is None:
                process.kill()
            shutil.rmtree(self.user_data, ignore_errors=True)
            shutil.rmtree(self.downloads, ignore_errors=True)


@pytest.fixture(scope="module")
def browser(request):
    b = Browser()
    request.addfinalizer(b.quit)
    return b


# Pixels of the canvas and of the newest decoded frames, read in one script (so no frame arrives
# between them: the path side keeps refining and sending frames).
PIXELS_JS = """
if (window.candela.drawPending) return null;
return arguments[0].map((source) => {
    let width, height, data;
    if (source === 'canvas') {
        const c = document.getElementById('view');
        width = c.width; height = c.height;
        data = c.getContext('2d').getImageData(0, 0, width, height).data;
    } else {
        const f = window.candela.frameData(source);
        if (!f) return null;
        width = f.width; height = f.height; data = f.data;
    }
    let s = '';
    for (let i = 0; i < data.length; i += 0x8000) s += String.fromCharCode.apply(null, data.subarray(i, i + 0x8000));
    return [width, height, btoa(s)];
});
"""


def is_raster(method) -> bool:
    """Methods drawn once per change (the raster mode); the others refine and keep sending frames."""
    return isinstance(method, str) and (method.startswith("raster") or method == "baked")


class Page:
    """The viewer page in the browser, with helpers to read and drive it."""

    def __init__(self, browser: Browser, server: ViewServer):
        self.browser, self.driver, self.server = browser, browser.driver, server

    def open(self):
        self.driver.get(self.server.url)
        wait_until(lambda: self.js("return !!(window.candelaStats && window.candelaStats.sceneReceived)"), 30, "the scene message")
        return self

    def js(self, script, *args):
        return self.driver.execute_script(script, *args)

    def stats(self):
        return self.js("return window.candelaStats")

    def status(self):
        return self.js("return window.candelaStatus")

    def pixels(self, *sources):
        """RGB bytes (H x W x 3) of the canvas and/or of the newest decoded frames of kinds 0, 1, 2,
        read at one instant (one script, when no decoded frame waits to be drawn, so the canvas shows
        the newest frames); one array for one source (default: the canvas), else a list."""
        results = wait_until(lambda: self.js(PIXELS_JS, list(sources or ["canvas"])), 10, "no frame waiting to be drawn")
        arrays = []
        for source, result in zip(sources or ["canvas"], results):
            assert result is not None, f"no frame of kind {source}"
            width, height, data = result
            arrays.append(np.frombuffer(base64.b64decode(data), np.uint8).reshape(height, width, 4)[:, :, :3].copy())
        return arrays[0] if len(arrays) == 1 else arrays

    def frame_size(self, kind):
        """The width and height of the newest frame of a kind, as sent (the JPEG's own size)."""
        return tuple(self.js("const f = window.candela.frameData(arguments[0]); return f ? [f.frameWidth, f.frameHeight] : null", kind)
                     or ())

    def frame_meta(self):
        return self.js("return [window.candelaStats.lastFrameSeq, window.candelaStats.lastFrameCameraId, window.candelaStats.framesDrawn]")

    def settle(self, change, quiet=0.6, timeout=60):
        """Runs change() (a change of settings or camera that gives new frames) and waits until a
        frame newer than the change has come and then none for `quiet` seconds."""
        before = self.frame_meta()[0]
        change()
        wait_until(lambda: self.frame_meta()[0] != before, timeout, "a new frame")
        self.quiet(quiet=quiet, timeout=timeout)

    def quiet(self, quiet=0.6, timeout=60):
        """Waits until no frame of the raster sides (drawn once per change; the heatmap too when both
        are raster) arrived for `quiet` seconds, and for the last one's draw. Progressive sides keep
        refining and sending frames: not waited for."""
        settings = self.js("return window.candela.settings")
        kinds = [k for k, side in ((0, "left"), (1, "right")) if is_raster(settings.get(side))]
        if settings.get("heatmap") and len(kinds) == 2:
            kinds.append(2)
        last, since = None, time.monotonic()
        deadline = time.monotonic() + timeout
        while True:
            seq = self.frame_meta()[0]
            now = [seq[k] for k in kinds]
            if now != last:
                last, since = now, time.monotonic()
            elif time.monotonic() - since >= quiet:
                break
            if time.monotonic() > deadline:
                raise AssertionError(f"frames kept coming for {timeout} s")
            time.sleep(0.05)
        time.sleep(0.15)  # the next animation frame draws the last decoded frame

    def set_settings(self, **settings):
        """Changes the settings the page's way (as its controls do), and waits for their frames."""
        current = self.js("return window.candela.settings")
        changed = {k: v for k, v in settings.items() if current.get(k) != v}
        if not changed:
            return
        apply = lambda: self.js("window.candela.setSettings(arguments[0])", changed)
        if set(changed) == {"split"}:  # the page composes the split itself: no new frame
            apply()
            time.sleep(0.2)
        else:
            self.settle(apply)

    def set_camera(self, camera):
        current = self.js("return window.candela.camera")
        if all(np.allclose(current[k], camera[k], atol=1e-6) for k in ("origin", "target", "up", "fov")):
            return
        sent = self.js("return window.candelaStats.lastCameraId")
        self.js("window.candela.setCamera(arguments[0])", camera)
        camera_id = wait_until(lambda: (lambda i: i if i > sent else None)(self.js("return window.candelaStats.lastCameraId")), 10,
                               "the camera message")
        wait_until(lambda: all(c is not None and c >= camera_id for c in self.frame_meta()[1][:2]), 60,
                   f"frames echoing camera id {camera_id}")
        self.quiet()

    def reset(self):
        """The initial camera and settings (other tests changed them: every page shares them)."""
        self.set_settings(**self.server.initial["settings"])
        self.set_camera(self.server.initial["camera"])

    def element(self, element_id):
        return self.driver.find_element(By.ID, element_id)


@pytest.fixture
def page(browser, server):
    p = Page(browser, server).open()
    # Frames arrive for a page that just connected, without any change.
    wait_until(lambda: all(n > 0 for n in p.stats()["framesByKind"][:2]), 30, "the first frames of both sides")
    p.reset()
    return p


def shot(page: Page, name: str):
    if SCREENSHOTS:
        target = REPO / "docs" / "images" / name
        target.parent.mkdir(parents=True, exist_ok=True)
        page.driver.save_screenshot(str(target))


# ------------------------------------------------------------------------------------------------
# The page's own files

def test_assets_are_self_contained():
    """The page fetches nothing from the internet: no absolute URL, no CDN, no web font."""
    for name in ("index.html", "app.js", "app.css"):
        text = (ASSETS / name).read_text()
        assert not re.search(r"(https?:)?//[a-z0-9.-]+\.[a-z]{2,}", text, re.I), f"{name} names an external resource"
        assert "@import" not in text and "@font-face" not in text, name
    html = (ASSETS / "index.html").read_text()
    for element_id in ("view", "left-method", "right-method", "shading", "reflection", "shadows", "aa", "gi", "exposure",
                       "tonemap", "heatmap", "save-exr", "save-png", "divider", "status", "inspector", "relmse", "block-mare"):
        assert f'id="{element_id}"' in html, element_id


def test_serves_its_three_files(server):
    for path, name, kind in (("/", "index.html", "text/html"), ("/app.js", "app.js", "javascript"), ("/app.css", "app.css", "text/css")):
        with urllib.request.urlopen(f"{server.base}{path}?token={server.token}", timeout=10) as response:
            assert response.status == 200
            assert kind in response.headers.get("Content-Type", ""), (path, response.headers.get("Content-Type"))
            assert response.read() == (ASSETS / name).read_bytes(), f"{path} is not viewer/assets/{name} (rebuild?)"


# ------------------------------------------------------------------------------------------------
# Safety

def http_status(server, target: str) -> tuple[int, bytes]:
    """The status and body of GET target, sent exactly as written (no normalisation)."""
    connection = http.client.HTTPConnection("127.0.0.1", server.port, timeout=10)
    try:
        connection.putrequest("GET", target, skip_host=True, skip_accept_encoding=True)
        connection.putheader("Host", f"127.0.0.1:{server.port}")
        connection.endheaders()
        response = connection.getresponse()
        return response.status, response.read()
    finally:
        connection.close()


def test_token_is_enforced(server):
    wrong = "0" * len(server.token)
    failures = []
    for path in ("/", "/app.js", "/app.css", "/save.exr?side=left", "/ws", "/nowhere"):
        separator = "&" if "?" in path else "?"
        for query in ("", f"{separator}token=", f"{separator}token={wrong}", f"{separator}token={server.token[:-1]}",
                      f"{separator}token={server.token}x", f"{separator}token={server.token.upper()}"):
            status, body = http_status(server, path + query)
            if status != 403:
                failures.append(f"GET {path + query} gave {status}")
    assert not failures, "\n".join(failures)
    # The right token opens the page.
    assert http_status(server, f"/?token={server.token}")[0] == 200
    # A WebSocket without the token (or with a wrong one) is refused before the upgrade.
    for token in (None, wrong, ""):
        with WebSocket(server.port, token) as ws:
            assert ws.status != 101, f"WebSocket with token {token!r} accepted"
            assert ws.status == 403, ws.response
    with WebSocket(server.port, server.token) as ws:
        assert ws.status == 101, ws.response


def test_traversal_is_refused(server):
    t = server.token
    failures = []
    for path in ("/../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/app.js/../../x", "/..%2f..%2fetc%2fpasswd",
                 "/%2e%2e%2f%2e%2e%2fetc%2fpasswd", "/%252e%252e/%252e%252e/etc/passwd", "/..\\..\\etc\\passwd",
                 "/etc/passwd", "//etc/passwd", "/index.html", "/viewer/assets/app.js", "/assets/app.js", "/app.js%00.html",
                 "/CMakeLists.txt", "/scenes/validation/cbox.xml", f"/{SCENE}", "/app.js/", "/app.js.bak", "/save.exr/x", "/ws/x"):
        status, body = http_status(server, f"{path}?token={t}")
        assert b"root:" not in body and b"<scene" not in body, path
        if status != 404:
            failures.append(f"GET {path} gave {status}")
    assert not failures, "\n".join(failures)
    assert server.alive()


HOSTILE = [
    ("bad JSON", "{"),
    ("not JSON", "hello there"),
    ("not an object", "[1, 2, 3]"),
    ("no type", '{"id": 1}'),
    ("type not a string", '{"type": 42}'),
    ("unknown type", '{"type": "warp-drive"}'),
    ("NaN camera", '{"type":"camera","id":1,"origin":[NaN,0,0],"target":[0,0,0],"up":[0,1,0],"fov":40}'),
    ("infinite camera", '{"type":"camera","id":1,"origin":[1e999,0,0],"target":[0,0,0],"up":[0,1,0],"fov":40}'),
    ("huge camera", '{"type":"camera","id":1,"origin":[1e308,1e308,1e308],"target":[0,0,0],"up":[0,1,0],"fov":40}'),
    ("degenerate camera", '{"type":"camera","id":1,"origin":[0,0,0],"target":[0,0,0],"up":[0,1,0],"fov":40}'),
    ("up along the view", '{"type":"camera","id":1,"origin":[0,0,3],"target":[0,0,0],"up":[0,0,1],"fov":40}'),
    ("camera vector of 2", '{"type":"camera","id":1,"origin":[0,0],"target":[0,0,0],"up":[0,1,0],"fov":40}'),
    ("camera vector of strings", '{"type":"camera","id":1,"origin":["a","b","c"],"target":[0,0,0],"up":[0,1,0],"fov":40}'),
    ("fov 0", '{"type":"camera","id":1,"origin":[0,0,3],"target":[0,0,0],"up":[0,1,0],"fov":0}'),
    ("fov huge", '{"type":"camera","id":1,"origin":[0,0,3],"target":[0,0,0],"up":[0,1,0],"fov":1e30}'),
    ("camera id huge", '{"type":"camera","id":1e300,"origin":[0,0,3],"target":[0,0,0],"up":[0,1,0],"fov":40}'),
    ("unknown method", '{"type":"settings","left":"no-such-method"}'),
    ("unknown shading", '{"type":"settings","shading":"toon"}'),
    ("aa huge", '{"type":"settings","aa":1000000000000}'),
    ("aa zero", '{"type":"settings","aa":0}'),
    ("aa not a number", '{"type":"settings","aa":"four"}'),
    ("exposure huge", '{"type":"settings","exposure":1e308}'),
    ("exposure NaN", '{"type":"settings","exposure":NaN}'),
    ("split outside", '{"type":"settings","split":7}'),
    ("heatmap not a bool", '{"type":"settings","heatmap":"yes"}'),
    ("inspect outside", '{"type":"inspect","x":1000000000000,"y":-5,"side":"left"}'),
    ("inspect side", '{"type":"inspect","x":1,"y":1,"side":"middle"}'),
    ("ping without id", '{"type":"ping"}'),
]


def test_hostile_messages_are_survived(server):
    with WebSocket(server.port, server.token) as ws:
        assert ws.status == 101, ws.response
        ws.send_json({"type": "hello"})
        before = ws.receive_json("scene", 30)
        failures = []
        for what, text in HOSTILE:
            ws.send_text(text)
            try:
                reply = ws.receive_json(("error", "pong", "pixel"), 10)
            except (AssertionError, EOFError) as e:
                failures.append(f"{what}: no reply ({e})")
                if isinstance(e, EOFError):
                    break
                continue
            if reply.get("type") != "error" or not isinstance(reply.get("message"), str) or not reply["message"]:
                failures.append(f"{what}: {reply}")
        # A binary message from a page is not part of the protocol either.
        ws.send(b"\x00\x01\x02", opcode=2)
        ws.send_json({"type": "ping", "id": 7})
        assert ws.receive_json("pong", 10)["id"] == 7, "the server stopped answering"
        ws.send_json({"type": "hello"})
        after = ws.receive_json("scene", 10)
        assert after["camera"] == before["camera"], "a refused message changed the camera"
        assert after["settings"] == before["settings"], "a refused message changed the settings"
        assert not failures, "messages without an error reply:\n" + "\n".join(failures)
    # A 1 MiB message: an error reply or a closed connection, and the server goes on serving.
    with WebSocket(server.port, server.token) as ws:
        ws.send_text('{"type":"settings","left":"' + "x" * (1 << 20) + '"}')
        try:
            ws.receive_json("error", 10)
        except (AssertionError, EOFError, ConnectionError, socket.timeout):
            pass
    with WebSocket(server.port, server.token) as ws:
        ws.send_json({"type": "hello"})
        assert ws.receive_json("scene", 10)["width"] == RES
    assert server.alive()


# ------------------------------------------------------------------------------------------------
# The page

def wait_path_spp(page: Page, spp=SPP, side="left", timeout=180):
    """Waits until the path side has at least spp samples per pixel (or is done) and a frame sent
    after that status has been drawn; returns the side's status."""
    def ready():
        s = page.status()
        if s and s.get(side, {}).get("method") == "path" and (s[side].get("spp", 0) >= spp or s[side].get("done")):
            return s[side]
        return None
    status = wait_until(ready, timeout, f"the path side ({side}) to reach {spp} spp")
    kind = 0 if side == "left" else 1
    seq = page.frame_meta()[0][kind]
    if not status.get("done"):
        wait_until(lambda: page.frame_meta()[0][kind] != seq, 30, "a path frame after that status")
    time.sleep(0.15)
    return status


@needs_browser
def test_canvas_shows_the_scene_like_candela_render(page, tmp_path):
    """Once the path side has its SPP samples, the canvas shows what `candela render` writes for
    the same scene and view, tonemapped alike (sRGB, exposure 0, clamped: `--png`).

    The tolerance: two renders at SPP with different seeds differ by their noise (measured here:
    `noise`, the mean absolute difference of 8-bit values between seeds 0 and 1); the viewer's
    image is such an independent render with at least SPP samples (so no noisier), sent as JPEG
    (quality 90, 4:2:0), whose error at 64 x 64 is 2.1-3.5 levels (measured in
    test_raster_toggles, where the raster side is deterministic and only JPEG separates the
    canvas from the CLI's image; chroma subsampling of the coloured walls' edges dominates). So
    the tolerance is noise + 5 levels (measured: 3.5 levels apart, noise 2.1, tolerance 7.1). The
    raster image (local illumination, no indirect light) is 27 levels away, which the test checks
    too (more than twice the tolerance): the comparison tells the methods apart."""
    page.set_settings(left="path", right="path", split=1.0)
    status = wait_path_spp(page)
    shown, left = page.pixels("canvas", 0)
    assert shown.shape == (RES, RES, 3)
    assert mad(shown, left) < 0.5, "the canvas (split 1) is not the left frame"
    # The viewer's image has at least SPP samples: its noise is at most that of an SPP render.
    spp = SPP
    reference, _ = cli_render(tmp_path, "path0", spp=spp)
    other_seed, _ = cli_render(tmp_path, "path1", "--seed", "1", spp=spp)
    raster, _ = cli_render(tmp_path, "raster", "--mode", "raster", "--reflection", page.js("return window.candela.settings.reflection"))
    noise = mad(reference, other_seed)
    difference = mad(shown, reference)
    tolerance = noise + JPEG_TOLERANCE
    print(f"\ncanvas ({status['spp']} spp when read) vs candela render at {spp} spp: {difference:.2f} levels "
          f"(noise between seeds {noise:.2f}, tolerance {tolerance:.2f});"
          f" raster vs path {mad(raster, reference):.2f}")
    assert mad(raster, reference) > 2 * tolerance, "the tolerance would not tell raster from path"
    assert difference <= tolerance


# The largest mean error JPEG (quality 90, 4:2:0) adds to a 64 x 64 view of the Cornell box, in
# 8-bit levels: measured 2.1 (Gouraud) to 3.5 (flat: sharp triangle edges) on the deterministic
# raster side against `candela render --mode raster` of the same options.
JPEG_TOLERANCE = 5.0


def raster_cli_args(settings) -> list[str]:
    return ["--mode", "raster", "--shading", settings["shading"], "--reflection", settings["reflection"], "--shadows", settings["shadows"],
            "--aa", str(settings["aa"])]


def floor_under_short_box(image: np.ndarray) -> float:
    """Mean brightness of the floor beside and in front of the short box, where its shadow falls:
    the light is above the room's centre and the box at x 0.33, z 0.3, so its shadow falls toward
    the camera and the green wall (the region is where raster renders with and without shadows
    differ most, rows 0.875-0.95 and columns 0.75-0.86 of the image)."""
    h, w = image.shape[:2]
    region = image[int(0.875 * h):int(0.95 * h), int(0.75 * w):int(0.86 * w)]
    return float(region.astype(np.float64).mean())


@needs_browser
def test_raster_toggles_change_the_image_as_they_should(page, tmp_path):
    """Each raster toggle gives the image `candela render --mode raster` gives with that option:
    the canvas is within JPEG's error of the CLI render of the same options and closest to it
    among all the options' renders; flat differs from Phong; shadows off brightens the floor
    under the short box (shadow maps and volumes darken it). (The reflection model is checked
    the same way, but the Cornell box is diffuse: Phong and Blinn-Phong give the same image.)"""
    page.set_settings(left="raster", right="raster", split=1.0, gi="none", aa=1, exposure=0.0, tonemap="srgb")
    base = page.js("return window.candela.settings")
    shown, cli = {}, {}
    for name, change in (("flat", {"shading": "flat", "shadows": "map"}), ("gouraud", {"shading": "gouraud", "shadows": "map"}),
                         ("phong", {"shading": "phong", "shadows": "map"}), ("no shadows", {"shading": "phong", "shadows": "none"}),
                         ("volumes", {"shading": "phong", "shadows": "volume"}),
                         ("reflection", {"shading": "phong", "shadows": "map",
                                         "reflection": "phong" if base["reflection"] == "blinn" else "blinn"})):
        page.set_settings(**change)
        shown[name] = page.pixels()
        cli[name], _ = cli_render(tmp_path, name.replace(" ", "_"), *raster_cli_args(dict(base, **change)))
    page.set_settings(shading="phong", shadows="map", reflection=base["reflection"])
    again = page.pixels()

    table = {a: {b: mad(shown[a], cli[b]) for b in cli} for a in cli}
    print("\ncanvas (rows) vs candela render --mode raster of the same options (columns), mean absolute difference (8-bit levels):")
    print(" " * 11 + "".join(f"{b:>11}" for b in cli))
    for a in cli:
        print(f"{a:>11}" + "".join(f"{table[a][b]:11.2f}" for b in cli))
    repeat = mad(again, shown["phong"])
    floor = {k: floor_under_short_box(shown[k]) for k in ("phong", "no shadows", "volumes")}
    print(f"the same settings twice: {repeat:.2f}; floor under the short box: shadow maps {floor['phong']:.1f}, "
          f"none {floor['no shadows']:.1f}, volumes {floor['volumes']:.1f}")
    for a in cli:
        assert table[a][a] < JPEG_TOLERANCE, f"{a}: the canvas is {table[a][a]:.2f} levels from candela render's image"
        assert table[a][a] == min(table[a].values()), f"{a}: the canvas is closer to another option's render"
    assert repeat < 0.5, "the raster side is not deterministic"
    assert mad(shown["flat"], shown["phong"]) > 2.0, "flat does not differ from Phong"
    assert floor["no shadows"] > floor["phong"] + 10, "shadows off does not brighten the floor under the box"
    assert floor["volumes"] < floor["no shadows"] - 10, "shadow volumes cast no shadow on the floor"


@needs_browser
def test_exposure_and_tonemap(page):
    page.set_settings(left="raster", right="raster", split=1.0)
    plain = page.pixels()
    page.set_settings(exposure=1.0)
    brighter = page.pixels()
    assert page.element("exposure").get_attribute("value") == "1"
    page.set_settings(exposure=0.0, tonemap="filmic")
    filmic = page.pixels()
    print(f"\nmean level: exposure 0 {plain.mean():.1f}, +1 EV {brighter.mean():.1f}, filmic {filmic.mean():.1f}")
    assert brighter.mean() > plain.mean() + 5
    assert mad(filmic, plain) > 2
    assert page.element("exposure-value").text.startswith("0.0")
    assert Select(page.element("tonemap")).first_selected_option.get_attribute("value") == "filmic"


def radius(camera) -> float:
    return math.dist(camera["origin"], camera["target"])


@needs_browser
def test_drag_moves_the_camera(page, server):
    """A simulated mouse drag orbits the camera: a camera message goes out, the server applies it
    (a new page's hello gets the new camera) and the image changes. The wheel zooms, shift-drag
    pans, W flies forward."""
    page.set_settings(left="raster", right="raster", split=1.0)
    before_image = page.pixels()
    before = page.js("return window.candela.camera")
    sent = page.stats()["cameraMessagesSent"]
    canvas = page.element("view")
    actions = ActionChains(page.driver).move_to_element(canvas).click_and_hold()
    for _ in range(6):
        actions.move_by_offset(15, 4)
    actions.release().perform()
    after = page.js("return window.candela.camera")
    wait_until(lambda: page.stats()["cameraMessagesSent"] > sent, 5, "a camera message")
    stats = page.stats()
    assert after["origin"] != before["origin"] and after["target"] == before["target"], "the drag did not orbit"
    assert radius(after) == pytest.approx(radius(before), rel=1e-4), "orbiting changed the distance to the target"
    last_id = stats["lastCameraId"]
    wait_until(lambda: page.frame_meta()[1][0] is not None and page.frame_meta()[1][0] >= last_id, 30, "a frame of the new camera")
    page.quiet()
    changed = mad(page.pixels(), before_image)
    print(f"\ndrag: {stats['cameraMessagesSent'] - sent} camera messages, image changed by {changed:.1f} levels")
    assert changed > 5, "the image did not change"
    camera = server.hello()["camera"]
    assert camera["origin"] == pytest.approx(after["origin"], abs=1e-4), "the server did not apply the camera"

    page.set_camera(before)
    page.driver.execute_script("arguments[0].focus()", canvas)
    ActionChains(page.driver).scroll_from_origin(ScrollOrigin.from_element(canvas), 0, -300).perform()
    zoomed = page.js("return window.candela.camera")
    assert radius(zoomed) < radius(before), "the wheel did not zoom in"
    ActionChains(page.driver).move_to_element(canvas).key_down(Keys.SHIFT).click_and_hold().move_by_offset(40, 0) \
        .move_by_offset(40, 0).release().key_up(Keys.SHIFT).perform()
    panned = page.js("return window.candela.camera")
    assert panned["target"] != zoomed["target"], "shift-drag did not pan"
    assert np.allclose(np.subtract(panned["target"], panned["origin"]), np.subtract(zoomed["target"], zoomed["origin"]), atol=1e-4), \
        "panning turned the camera"
    page.driver.execute_script("arguments[0].focus()", canvas)
    ActionChains(page.driver).key_down("w").pause(0.3).key_up("w").perform()
    flown = page.js("return window.candela.camera")
    forward = np.subtract(panned["target"], panned["origin"])
    assert np.dot(np.subtract(flown["origin"], panned["origin"]), forward) > 0, "W did not fly forward"
    assert np.allclose(np.subtract(flown["target"], flown["origin"]), forward, atol=1e-4), "flying turned the camera"


@needs_browser
def test_pixel_inspector(page):
    """A click (no drag) asks for the pixel under the cursor, on the side under the cursor."""
    page.set_settings(left="path", right="raster", split=0.5)
    canvas = page.element("view")
    size = canvas.size
    sent = page.stats()["cameraMessagesSent"]
    for side, dx in (("left", -size["width"] // 4), ("right", size["width"] // 4)):
        before = page.js("return window.candelaStats.lastPixel")
        ActionChains(page.driver).move_to_element_with_offset(canvas, dx, size["height"] // 4).click().perform()
        pixel = wait_until(lambda: (lambda p: p if p and p != before else None)(page.js("return window.candelaStats.lastPixel")), 10,
                           "the pixel answer")
        text = page.element("inspector").text
        print(f"\ninspector: {text}")
        assert pixel["side"] == side
        expected_x = int((size["width"] / 2 + dx) * RES / size["width"])
        assert abs(pixel["x"] - expected_x) <= 1 and abs(pixel["y"] - int(0.75 * RES)) <= 1, pixel
        assert len(pixel["radiance"]) == 3 and len(pixel["ci95"]) == 3
        assert all(math.isfinite(v) and v >= 0 for v in pixel["radiance"] + pixel["ci95"])
        assert pixel["spp"] >= 1
        assert "\u00b1" in text and side in text
    assert page.stats()["cameraMessagesSent"] == sent, "a click moved the camera"


@needs_browser
def test_split_view_and_heatmap(page, server):
    """The method selectors set the sides; the divider drags; left of it is the left frame, right
    of it the right frame; the heatmap toggle shows the heatmap frame; relMSE and block MARE are
    shown as numbers."""
    methods = page.js("return window.candela.scene.methods")
    assert {"path", "raster"} <= set(methods), methods
    page.set_settings(left="raster", right="path", split=0.5)

    def choose():
        Select(page.element("left-method")).select_by_value("path")
        Select(page.element("right-method")).select_by_value("raster")
    page.settle(choose)
    wait_until(lambda: (page.status() or {}).get("left", {}).get("method") == "path" and page.status()["right"]["method"] == "raster",
               30, "the status of path | raster")
    canvas, divider = page.element("view"), page.element("divider")
    ActionChains(page.driver).click_and_hold(divider).move_by_offset(-canvas.size["width"] // 4, 0).release().perform()
    split = page.js("return window.candela.split")
    assert split == pytest.approx(0.25, abs=0.03), split
    wait_until(lambda: server.hello()["settings"]["split"] == pytest.approx(split, abs=1e-3), 10, "the split at the server")
    wait_path_spp(page)
    page.quiet(quiet=1.0)
    shown, left, right = page.pixels("canvas", 0, 1)
    x = round(split * RES)
    assert mad(shown[:, :x], left[:, :x]) < 0.5 and mad(shown[:, x:], right[:, x:]) < 0.5, "the split is not composed"
    assert mad(left, right) > 5
    assert page.frame_size(0) == page.frame_size(1) == (RES, RES)
    status = wait_until(lambda: (lambda s: s if s and isinstance(s.get("relmse"), (int, float)) and isinstance(s.get("block_mare"), (int, float))
                                 else None)(page.status()), 30, "relmse and block_mare in the status")
    time.sleep(0.5)
    # The status and the numbers it put on the page, read in one script: the path side goes on
    # refining, and a status arriving between two reads would pair numbers of different moments.
    status, relmse_text, block_mare_text = page.js(
        "return [window.candelaStatus, document.getElementById('relmse').textContent, document.getElementById('block-mare').textContent]")
    relmse, block_mare = float(relmse_text), float(block_mare_text)
    print(f"\nstatus: relMSE {status['relmse']}, block MARE {status['block_mare']}; shown {relmse}, {block_mare}; "
          f"{page.element('status').text!r}")
    assert relmse == pytest.approx(status["relmse"], rel=1e-3) and block_mare == pytest.approx(status["block_mare"], rel=1e-3)
    assert relmse > 0 and block_mare > 0

    heat_frames = page.stats()["framesByKind"][2]
    page.settle(lambda: page.element("heatmap").click(), quiet=1.0)
    wait_until(lambda: page.stats()["framesByKind"][2] > heat_frames, 30, "a heatmap frame")
    page.quiet(quiet=1.0)
    heat, heat_frame = page.pixels("canvas", 2)
    assert mad(heat, heat_frame) < 0.5, "the canvas does not show the heatmap"
    assert mad(heat, shown) > 5, "the heatmap toggle did not change the canvas"
    assert not page.element("divider").is_displayed()
    assert page.frame_size(2) == (RES, RES), f"the heatmap frame is {page.frame_size(2)}, not the film's {RES} x {RES}"
    page.element("heatmap").click()
    wait_until(lambda: not server.hello()["settings"]["heatmap"], 10, "heatmap off at the server")


@needs_browser
def test_save_exr_and_png(page, server, tmp_path):
    """Save EXR downloads the current accumulation (the EXR `candela render` writes, metadata
    included); Save PNG downloads the canvas as shown."""
    page.set_settings(left="path", right="raster")
    wait_path_spp(page)
    link = page.element("save-exr")
    href = link.get_attribute("href")
    assert href.startswith(server.base + "/save.exr?") and f"token={server.token}" in href and "side=left" in href, href
    assert link.get_attribute("download") == "candela-view.exr"
    with urllib.request.urlopen(href, timeout=30) as response:
        assert response.status == 200
        disposition = response.headers.get("Content-Disposition", "")
        data = response.read()
    assert "attachment" in disposition and "candela-view.exr" in disposition, disposition
    assert data[:4] == EXR_MAGIC, data[:16]
    header = exr_header(data)
    assert {"R", "G", "B"} <= set(header["channels"]), header["channels"]
    x0, y0, x1, y1 = header["dataWindow"]
    assert (x1 - x0 + 1, y1 - y0 + 1) == (RES, RES)
    path = tmp_path / "saved.exr"
    path.write_bytes(data)
    candela = import_candela()
    if candela is not None:
        image = candela.read_image(str(path))
        print(f"\nsaved EXR: {image!r}, metadata {image.metadata}")
        assert (image.width, image.height) == (RES, RES) and {"R", "G", "B"} <= set(image.channels)
        rgb = np.asarray(image.rgb())
        assert np.isfinite(rgb).all() and rgb.mean() > 0
        assert int(image.metadata.get("candela.spp", 0)) >= SPP, image.metadata
    status, body = http_status(server, f"/save.exr?token={server.token}&side=right")
    assert status == 200 and body[:4] == EXR_MAGIC, f"right side: {status}"
    assert http_status(server, f"/save.exr?token={server.token}&side=middle")[0] != 200

    # Save PNG: the canvas as shown, downloaded by the browser (raster sides: a still view).
    page.set_settings(left="raster", right="raster", shading="flat")
    page.element("save-png").click()
    png = wait_until(lambda: next(iter(page.browser.downloads.glob("candela-view*.png")), None), 30, "the PNG download")
    wait_until(lambda: png.stat().st_size > 0 and not list(page.browser.downloads.glob("*.crdownload")), 10, "the download to finish")
    assert mad(read_png(png), page.pixels()) < 0.5


def import_candela():
    try:
        sys.path.insert(0, str(BINARY.parent / "python"))
        import candela
        return candela
    except ImportError:
        return None


@needs_browser
def test_ten_pages_all_receive_frames(page, server):
    """Ten pages at once: each gets frames on connecting, and a camera move in one reaches all
    (as a camera message and as frames of that camera); closing nine leaves the server serving."""
    driver = page.driver
    main = driver.current_window_handle
    handles = []
    try:
        for _ in range(9):
            driver.switch_to.new_window("tab")
            driver.get(server.url)
            handles.append(driver.current_window_handle)
        for handle in handles:
            driver.switch_to.window(handle)
            wait_until(lambda: page.js("return !!window.candelaStats && window.candelaStats.framesReceived > 0"), 30, "frames in every page")
        driver.switch_to.window(main)
        page.js("window.candela.orbit(40, 0)")
        camera_id = wait_until(lambda: page.stats()["lastCameraId"] or None, 5, "the camera message")
        camera = page.js("return window.candela.camera")
        received = [page.stats()["framesReceived"]]
        for handle in handles:
            driver.switch_to.window(handle)
            wait_until(lambda: np.allclose(page.js("return window.candela.camera")["origin"], camera["origin"], atol=1e-5), 30,
                       "the camera in every page")
            wait_until(lambda: max(c or 0 for c in page.frame_meta()[1]) >= camera_id, 30, "frames of the new camera in every page")
            received.append(page.stats()["framesReceived"])
        print(f"\nframes received by the ten pages: {received}")
        assert len(received) == 10 and all(n > 0 for n in received)
    finally:
        for handle in handles:
            driver.switch_to.window(handle)
            driver.close()
        driver.switch_to.window(main)
    assert server.hello()["width"] == RES  # closed tabs left it serving
    assert server.alive()


@needs_browser
def test_reconnects_politely(browser):
    """When the server goes away the page says so and keeps trying (its own server, stopped)."""
    s = ViewServer()
    try:
        p = Page(browser, s).open()
        s.stop()
        message = wait_until(lambda: (lambda e: e.text if e.is_displayed() and e.text else None)(p.element("connection")), 15,
                             "the disconnection message")
        assert "reconnect" in message.lower(), message
        assert not p.stats()["connected"]
        wait_until(lambda: "token" in p.element("connection").text, 30, "the hint to open the new URL")
    finally:
        s.stop()


@needs_browser
@pytest.mark.skipif(not SCREENSHOTS, reason="CANDELA_VIEWER_SCREENSHOTS=1 takes the documentation's screenshots")
def test_screenshots(browser):
    """docs/images/viewer-split.png and viewer-heatmap.png: the Cornell box at 256 x 256, path
    tracer left (64 spp or more) and raster right, then the heatmap of the pair."""
    s = ViewServer(res=256, spp=64)
    try:
        p = Page(browser, s).open()
        wait_until(lambda: all(n > 0 for n in p.stats()["framesByKind"][:2]), 60, "the first frames")
        p.js("window.candela.setSettings(arguments[0])", {"left": "path", "right": "raster", "split": 0.5, "heatmap": False})
        wait_until(lambda: (p.status() or {}).get("left", {}).get("method") == "path", 30, "path on the left")
        wait_path_spp(p, spp=64, timeout=300)
        p.quiet(quiet=1.0)
        ActionChains(p.driver).move_to_element_with_offset(p.element("view"), -60, 80).click().perform()
        wait_until(lambda: p.js("return window.candelaStats.lastPixel"), 10, "the inspector")
        time.sleep(0.5)
        shot(p, "viewer-split.png")
        p.element("heatmap").click()
        wait_until(lambda: p.stats()["framesByKind"][2] > 0, 30, "a heatmap frame")
        time.sleep(1.0)
        shot(p, "viewer-heatmap.png")
    finally:
        s.stop()


# ------------------------------------------------------------------------------------------------
# Measurements (printed and written to bench/results; no speed is asserted)

MOTION_JS = """
const seconds = arguments[0], done = arguments[arguments.length - 1];
const s = window.candelaStats;
const f0 = s.framesByKind.slice(), b0 = s.bytesReceived, n0 = s.framesReceived, m0 = s.cameraMessagesSent, l0 = s.latencyCount;
const t0 = performance.now();
let fpsSum = 0, fpsCount = 0;
function step(now) {
    window.candela.orbit(2, 0);
    if (now - t0 >= 1000) { fpsSum += s.fps; fpsCount++; }
    if (now - t0 < seconds * 1000) { requestAnimationFrame(step); return; }
    const t = (performance.now() - t0) / 1000;
    done({seconds: t, left: (s.framesByKind[0] - f0[0]) / t, right: (s.framesByKind[1] - f0[1]) / t,
          bytesPerFrame: (s.bytesReceived - b0) / Math.max(1, s.framesReceived - n0),
          cameraMessages: (s.cameraMessagesSent - m0) / t, pageFps: fpsCount ? fpsSum / fpsCount : null,
          latencyMs: s.latencyCount > l0 ? s.latencyMs : null});
}
requestAnimationFrame(step);
"""

LATENCY_JS = """
const count = arguments[0], done = arguments[arguments.length - 1];
const s = window.candelaStats, out = [];
function next() {
    if (out.length >= count) { done(out); return; }
    const c0 = s.latencyCount, t0 = performance.now();
    window.candela.orbit(3, 0);
    (function wait() {
        if (s.latencyCount > c0) { out.push(s.latencySamples[s.latencySamples.length - 1]); setTimeout(next, 150); }
        else if (performance.now() - t0 > 5000) { out.push(null); setTimeout(next, 150); }
        else requestAnimationFrame(wait);
    })();
}
next();
"""


@needs_browser
@pytest.mark.skipif(os.environ.get("CANDELA_VIEWER_BENCH") != "1",
                    reason="CANDELA_VIEWER_BENCH=1 runs the measurement (70 s; its figures need an otherwise idle machine)")
def test_measurements(browser, tmp_path):
    """512 x 512: raster frames received per second during continuous camera motion, the latency
    from a camera message to its frame on screen, and the path side's samples/s against
    `candela render` of the same scene and spp (all threads both)."""
    res, spp = 512, 32
    today = datetime.date.today().isoformat()
    lines = [f"candela view measurements, {today} (tests/viewer/test_viewer.py::test_measurements)",
             f"machine: {os.cpu_count()} cores, {cpu_model()}; {chromium_version()} headless",
             f"commit {git_commit()}; scene {SCENE.relative_to(REPO)} -D res={res} -D spp={spp}; "
             f"load average before the run {os.getloadavg()[0]:.2f} (other work on the machine shares its 2 cores)", ""]
    s = ViewServer(res=res, spp=spp)
    try:
        initial = s.hello()
        p = Page(browser, s).open()
        wait_until(lambda: all(n > 0 for n in p.stats()["framesByKind"][:2]), 60, "the first frames")
        for left, right in (("raster", "raster"), ("path", "raster")):
            p.js("window.candela.setSettings(arguments[0])", {"left": left, "right": right, "shadows": "map", "shading": "phong",
                                                               "heatmap": False, "split": 0.5})
            time.sleep(1.0)
            m = p.driver.execute_async_script(MOTION_JS, 5)
            raster_fps = m["left"] if left == "raster" else m["right"]
            lines.append(f"{left} | {right}, shadow maps, continuous orbit for {m['seconds']:.1f} s: raster frames received "
                         f"{raster_fps:.1f}/s (left {m['left']:.1f}, right {m['right']:.1f}; the page's own fps {fmt(m['pageFps'])}), "
                         f"{m['cameraMessages']:.1f} camera messages/s, {m['bytesPerFrame'] / 1024:.1f} kB/frame, "
                         f"latency {fmt(m['latencyMs'])} ms (average of the last 20, under motion)")
            assert m["left"] + m["right"] > 0, "no frames during the motion"
        p.js("window.candela.setSettings(arguments[0])", {"left": "raster", "right": "raster"})
        time.sleep(1.0)
        latencies = [x for x in p.driver.execute_async_script(LATENCY_JS, 20) if x is not None]
        assert latencies, "no frame echoed a camera id"
        lines.append(f"raster | raster, single camera moves 150 ms apart: camera message to frame on screen mean {np.mean(latencies):.1f} ms, "
                     f"median {np.median(latencies):.1f} ms, max {np.max(latencies):.1f} ms ({len(latencies)} moves)")

        # The path side alone (the raster side idles once drawn), from the scene's camera.
        p.js("window.candela.setSettings(arguments[0])", {"left": "path", "right": "raster"})
        time.sleep(0.3)
        p.js("window.candela.setCamera(arguments[0])", initial["camera"])
        time.sleep(0.5)
        f0, t0 = p.stats()["framesByKind"][0], time.monotonic()
        viewer = wait_path_spp(p, spp=spp, timeout=600)
        path_frames = (p.stats()["framesByKind"][0] - f0) / (time.monotonic() - t0)
        p.js("window.candela.setSettings(arguments[0])", {"left": "raster", "right": "raster"})  # stop the path tracer
        time.sleep(0.5)
        # The server's own rate, without the browser: a WebSocket client of the standard library.
        for left, right in (("raster", "raster"), ("path", "raster")):
            rate = client_motion_rate(s, left, right, 5.0)
            lines.append(f"{left} | {right}, the same motion from a Python WebSocket client (no browser): "
                         f"raster frames received {rate['raster']:.1f}/s, {rate['cameras']:.1f} camera messages/s")
    finally:
        s.stop()
    # The CLI alone on the machine (the viewer keeps refining while it runs: stopped first).
    _, summary = cli_render(tmp_path, "path512", res=res, spp=spp)
    cli = parse_samples_per_second(summary)
    ratio = viewer["samples_per_second"] / cli if cli else float("nan")
    lines.append(f"path side: {viewer['spp']} spp in {viewer['seconds']:.2f} s, {viewer['samples_per_second'] / 1e6:.3f} M samples/s "
                 f"(with the browser on the same 2 cores); candela render: {summary.split(': ', 1)[-1]!r}: the viewer has "
                 f"{ratio * 100:.1f}% of the CLI's samples/s; path frames received while it rendered {path_frames:.1f}/s")
    text = "\n".join(lines) + "\n"
    print("\n" + text)
    out = REPO / "bench" / "results" / f"viewer_{today}.txt"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)


def client_motion_rate(s: ViewServer, left: str, right: str, seconds: float) -> dict:
    """Orbits the camera at 60 messages/s from a Python client; frames/s of the raster side received."""
    with WebSocket(s.port, s.token) as ws:
        ws.send_json({"type": "hello"})
        scene = ws.receive_json("scene", 30)
        ws.send_json({"type": "settings", "left": left, "right": right, "heatmap": False})
        time.sleep(1.0)
        counts, stop = [0, 0, 0], threading.Event()

        def read():
            while not stop.is_set():
                try:
                    opcode, payload = ws.receive(0.5)
                except (socket.timeout, OSError, EOFError):
                    continue
                if opcode == 2 and payload:
                    counts[payload[0]] += 1
        reader = threading.Thread(target=read, daemon=True)
        reader.start()
        camera = scene["camera"]
        target, origin = np.array(camera["target"], float), np.array(camera["origin"], float)
        start_counts, t0, sent, angle = None, time.monotonic(), 0, 0.0
        while time.monotonic() - t0 < seconds:
            angle += 0.01
            offset = origin - target
            rotated = [offset[0] * math.cos(angle) + offset[2] * math.sin(angle), offset[1],
                       -offset[0] * math.sin(angle) + offset[2] * math.cos(angle)]
            sent += 1
            ws.send_json({"type": "camera", "id": 1_000_000 + sent, "origin": list(target + rotated), "target": camera["target"],
                          "up": camera["up"], "fov": camera["fov"]})
            if start_counts is None:
                start_counts = counts.copy()
            time.sleep(1 / 60)
        elapsed = time.monotonic() - t0
        stop.set()
        reader.join(2)
        kind = 0 if is_raster(left) else 1
        return {"raster": (counts[kind] - start_counts[kind]) / elapsed, "cameras": sent / elapsed}


def parse_samples_per_second(summary: str):
    m = re.search(r"([\d.]+)\s*([kMG]?)\s*samples/s", summary)
    if not m:
        return None
    return float(m.group(1)) * {"": 1, "k": 1e3, "M": 1e6, "G": 1e9}[m.group(2)]


def fmt(v):
    return "-" if v is None else f"{v:.1f}"


def cpu_model():
    try:
        return next(l.split(":", 1)[1].strip() for l in Path("/proc/cpuinfo").read_text().splitlines() if l.startswith("model name"))
    except (OSError, StopIteration):
        return platform.processor()


def chromium_version():
    try:
        return subprocess.run([CHROMIUM, "--version"], capture_output=True, text=True, timeout=30).stdout.strip()
    except (OSError, subprocess.TimeoutExpired):
        return "chromium ?"


def git_commit():
    try:
        return subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"], capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.TimeoutExpired):
        return "?"
