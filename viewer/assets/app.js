// candela view: the page. It shows the frames the server sends (JPEG, already tonemapped) on one
// canvas, left and right of a draggable divider or the heatmap, sends the camera and the settings,
// and measures what it receives (window.candelaStats). The protocol is in docs/viewer.md.
'use strict';

(function () {
    const token = new URLSearchParams(location.search).get('token') || '';
    const tokenQuery = 'token=' + encodeURIComponent(token);

    const KIND_LEFT = 0, KIND_RIGHT = 1, KIND_HEATMAP = 2;
    const KIND_NAMES = ['left', 'right', 'heatmap'];
    const LATENCY_WINDOW = 20;       // camera-to-frame latencies averaged
    const FPS_WINDOW_MS = 1000;      // frames per second over the last second
    const CLICK_SLOP = 4;            // CSS pixels a press may move and still be a click

    // ---------------------------------------------------------------- measurements (for tests)
    const stats = {
        connected: false,
        sceneReceived: false,
        connects: 0,
        reconnects: 0,
        fps: 0,                  // frames/s received for the raster side(s) (all frames if none is raster)
        fpsLeft: 0,
        fpsRight: 0,
        fpsHeatmap: 0,
        latencyMs: null,         // average over the last 20 camera ids echoed by a drawn frame
        latencySamples: [],
        latencyCount: 0,         // latencies measured since the page opened
        framesReceived: 0,
        framesByKind: [0, 0, 0],
        framesDrawn: 0,
        bytesReceived: 0,
        lastFrameBytes: 0,
        lastFrameSeq: [null, null, null],
        lastFrameCameraId: [null, null, null],
        decodeErrors: 0,
        cameraMessagesSent: 0,
        lastCameraId: 0,
        lastEchoedCameraId: 0,
        settingsMessagesSent: 0,
        messagesReceived: 0,
        errors: [],              // messages of the server's error replies (the last 20)
        lastPixel: null,         // the last inspector answer
    };
    window.candelaStats = stats;
    window.candelaStatus = null;

    // ---------------------------------------------------------------- state
    let ws = null;
    let reconnectDelay = 500;
    let reconnectTimer = null;
    let failedConnects = 0;
    let scene = null;                // the scene message
    let width = 0, height = 0;       // film size
    let camera = null;               // {origin, target, up, fov}
    let worldUp = [0, 1, 0];
    let sceneSize = 1;               // bounding box diagonal
    const settings = {};             // the current settings as this page knows them
    let split = 0.5;
    const bitmaps = [null, null, null];
    const bitmapMeta = [null, null, null];   // {seq, cameraId} of the bitmap shown
    const frameTimes = [[], [], []];
    const cameraSentAt = new Map();          // camera id -> performance.now() when sent
    let cameraDirty = false;
    let highestFrameCameraId = 0;            // camera ids this page sends start above what frames echoed
    let pendingSettings = null;
    const localEditAt = {};                  // settings key -> when this page last changed it
    let needsDraw = true;
    const keys = new Set();
    let lastTick = performance.now();

    // ---------------------------------------------------------------- elements
    const $ = (id) => document.getElementById(id);
    let canvas, ctx, stage, divider, statusEl, inspectorEl, connectionEl, messagesEl;
    const controls = {};   // settings key -> element

    // ---------------------------------------------------------------- vectors
    const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
    const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    const mul = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
    const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    const length = (a) => Math.sqrt(dot(a, a));
    const normalize = (a) => { const l = length(a); return l > 0 ? mul(a, 1 / l) : a.slice(); };
    const finiteVec = (a) => Array.isArray(a) && a.length === 3 && a.every(Number.isFinite);
    // Rotates v about the unit axis k by angle (Rodrigues).
    function rotate(v, k, angle) {
        const c = Math.cos(angle), s = Math.sin(angle);
        return add(add(mul(v, c), mul(cross(k, v), s)), mul(k, dot(k, v) * (1 - c)));
    }

    // ---------------------------------------------------------------- connection
    function wsUrl() {
        const url = new URL('ws?' + tokenQuery, location.href);
        url.protocol = location.protocol === 'https:' ? 'wss:' : 'ws:';
        return url.href;
    }

    function connect() {
        reconnectTimer = null;
        let socket;
        try {
            socket = new WebSocket(wsUrl());
        } catch (e) {
            scheduleReconnect();
            return;
        }
        socket.binaryType = 'arraybuffer';
        ws = socket;
        socket.onopen = () => {
            if (ws !== socket) return;
            stats.connected = true;
            stats.connects++;
            if (stats.connects > 1) stats.reconnects++;
            failedConnects = 0;
            reconnectDelay = 500;
            showConnection(null);
            send({type: 'hello'});
        };
        socket.onmessage = (event) => {
            if (ws !== socket) return;
            if (typeof event.data === 'string') onText(event.data);
            else onFrame(event.data);
        };
        socket.onclose = () => {
            if (ws !== socket) return;
            ws = null;
            if (stats.connected) failedConnects = 0; else failedConnects++;
            stats.connected = false;
            scheduleReconnect();
        };
        socket.onerror = () => { /* onclose follows */ };
    }

    function scheduleReconnect() {
        if (reconnectTimer !== null) return;
        const seconds = (reconnectDelay / 1000).toFixed(reconnectDelay < 1000 ? 1 : 0);
        let text = 'Connection to the server lost; reconnecting in ' + seconds + ' s\u2026';
        if (failedConnects >= 4) {
            text += '\nIf candela view was restarted, open the new URL it printed (its token changes at every start).';
        }
        showConnection(text);
        reconnectTimer = setTimeout(connect, reconnectDelay);
        reconnectDelay = Math.min(reconnectDelay * 2, 5000);
    }

    function showConnection(text) {
        if (!connectionEl) return;
        if (text === null) {
            connectionEl.classList.add('hidden');
        } else {
            connectionEl.textContent = text;
            connectionEl.classList.remove('hidden');
        }
    }

    function send(message) {
        if (!ws || ws.readyState !== WebSocket.OPEN) return false;
        ws.send(JSON.stringify(message));
        return true;
    }

    // ---------------------------------------------------------------- server -> page
    function onText(text) {
        stats.messagesReceived++;
        let message;
        try {
            message = JSON.parse(text);
        } catch (e) {
            return;
        }
        if (!message || typeof message !== 'object') return;
        switch (message.type) {
        case 'scene': onScene(message); break;
        case 'status': onStatus(message); break;
        case 'settings': if (message.settings && typeof message.settings === 'object') applySettings(message.settings); break;
        case 'camera': onRemoteCamera(message); break;
        case 'pixel': onPixel(message); break;
        case 'error': onError(message); break;
        case 'pong': break;
        default: break;
        }
    }

    function onScene(message) {
        scene = message;
        width = Math.max(1, message.width | 0);
        height = Math.max(1, message.height | 0);
        if (canvas.width !== width || canvas.height !== height) {
            canvas.width = width;
            canvas.height = height;
        }
        if (message.camera) setCameraFields(message.camera);
        if (camera && finiteVec(camera.up)) worldUp = normalize(camera.up);
        if (message.bbox && finiteVec(message.bbox.min) && finiteVec(message.bbox.max)) {
            sceneSize = length(sub(message.bbox.max, message.bbox.min)) || 1;
        } else if (camera) {
            sceneSize = length(sub(camera.target, camera.origin)) || 1;
        }
        fillMethods(message.methods || []);
        if (message.settings) applySettings(message.settings, false);
        stats.sceneReceived = true;
        layout();
        needsDraw = true;
    }

    function setCameraFields(c) {
        if (!finiteVec(c.origin) || !finiteVec(c.target) || !finiteVec(c.up) || !Number.isFinite(c.fov)) return;
        camera = {origin: c.origin.slice(), target: c.target.slice(), up: c.up.slice(), fov: c.fov};
    }

    function onRemoteCamera(message) {
        // Another page moved the camera: follow it (and do not send it back).
        setCameraFields(message);
    }

    function fillMethods(methods) {
        for (const id of ['left-method', 'right-method']) {
            const select = $(id);
            const current = select.value;
            select.textContent = '';
            for (const m of methods) {
                const option = document.createElement('option');
                option.value = m;
                option.textContent = m;
                select.appendChild(option);
            }
            if (methods.includes(current)) select.value = current;
        }
    }

    // Settings from the server. A value this page changed in the last moments wins over the
    // server's echo of an older one (a slider being dragged does not jump back).
    function applySettings(s, remote = true) {
        const now = performance.now();
        for (const [key, value] of Object.entries(s)) {
            if (remote && now - (localEditAt[key] || -1e9) < 400) continue;
            settings[key] = value;
            const el = controls[key];
            if (key === 'split') {
                if (Number.isFinite(value) && !dividerDrag) split = Math.min(1, Math.max(0, value));
                continue;
            }
            if (!el) continue;
            if (el.type === 'checkbox') el.checked = !!value;
            else if (el.tagName === 'SELECT') {
                const v = String(value);
                if (![...el.options].some((o) => o.value === v)) {
                    const option = document.createElement('option');
                    option.value = v;
                    option.textContent = v;
                    el.appendChild(option);
                }
                el.value = v;
            } else el.value = String(value);
        }
        updateDisplay();
        needsDraw = true;
    }

    function onStatus(message) {
        window.candelaStatus = message;
        renderStatus();
        const number = (v) => (typeof v === 'number' && Number.isFinite(v)) ? formatNumber(v) : '\u2014';
        $('relmse').textContent = number(message.relmse);
        $('block-mare').textContent = number(message.block_mare);
    }

    function onPixel(message) {
        stats.lastPixel = message;
        const r = message.radiance || [], ci = message.ci95 || [];
        const parts = ['R', 'G', 'B'].map((c, i) => c + ' ' + formatNumber(r[i]) + ' \u00b1 ' + formatNumber(ci[i]));
        inspectorEl.textContent = message.side + ' pixel (' + message.x + ', ' + message.y + '): ' + parts.join(', ') +
            ' \u00b7 ' + message.spp + ' spp';
        inspectorEl.classList.add('value');
    }

    let messageTimer = null;
    function onError(message) {
        stats.errors.push(String(message.message));
        if (stats.errors.length > 20) stats.errors.shift();
        messagesEl.textContent = 'Server: ' + message.message;
        clearTimeout(messageTimer);
        messageTimer = setTimeout(() => { messagesEl.textContent = ''; }, 6000);
    }

    function onFrame(buffer) {
        const bytes = new Uint8Array(buffer);
        if (bytes.length < 9) return;
        const view = new DataView(buffer);
        const kind = bytes[0];
        if (kind > KIND_HEATMAP) return;
        const seq = view.getUint32(1, true);
        const cameraId = view.getUint32(5, true);
        const now = performance.now();
        stats.framesReceived++;
        stats.framesByKind[kind]++;
        if (cameraId > highestFrameCameraId) highestFrameCameraId = cameraId;
        stats.bytesReceived += bytes.length;
        stats.lastFrameBytes = bytes.length;
        frameTimes[kind].push(now);
        const blob = new Blob([bytes.subarray(9)], {type: 'image/jpeg'});
        createImageBitmap(blob).then((bitmap) => {
            // Decodes may finish out of order: keep the newest frame of each kind.
            const shown = bitmapMeta[kind];
            if (shown && seq < shown.seq && shown.seq - seq < 0x80000000) {
                bitmap.close();
                return;
            }
            if (bitmaps[kind]) bitmaps[kind].close();
            bitmaps[kind] = bitmap;
            bitmapMeta[kind] = {seq, cameraId, drawn: false};
            stats.lastFrameSeq[kind] = seq;
            stats.lastFrameCameraId[kind] = cameraId;
            needsDraw = true;
        }, () => { stats.decodeErrors++; });
    }

    // ---------------------------------------------------------------- drawing
    function draw() {
        needsDraw = false;
        if (!width) return;
        const heat = !!settings.heatmap;
        if (heat) {
            drawFitted(ctx, bitmaps[KIND_HEATMAP]);
        } else {
            const splitX = Math.round(split * width);
            drawSide(KIND_LEFT, 0, splitX);
            drawSide(KIND_RIGHT, splitX, width - splitX);
        }
        stats.framesDrawn++;
        // Latency: from the camera message to the first frame on screen that echoes its id.
        const now = performance.now();
        for (const kind of (heat ? [KIND_HEATMAP] : [KIND_LEFT, KIND_RIGHT])) {
            const meta = bitmapMeta[kind];
            if (!meta || meta.drawn) continue;
            meta.drawn = true;
            const sent = cameraSentAt.get(meta.cameraId);
            if (sent !== undefined) {
                stats.latencySamples.push(now - sent);
                stats.latencyCount++;
                if (stats.latencySamples.length > LATENCY_WINDOW) stats.latencySamples.shift();
                stats.latencyMs = stats.latencySamples.reduce((a, b) => a + b, 0) / stats.latencySamples.length;
                stats.lastEchoedCameraId = meta.cameraId;
                for (const id of cameraSentAt.keys()) if (id <= meta.cameraId) cameraSentAt.delete(id);
            }
        }
    }

    // Draws a frame over the whole film; one of another size (not the protocol's W x H) keeps its
    // aspect ratio, centred on black.
    function drawFitted(g, bitmap) {
        if (!bitmap || bitmap.width !== width || bitmap.height !== height) {
            g.fillStyle = '#000';
            g.fillRect(0, 0, width, height);
        }
        if (!bitmap) return;
        if (bitmap.width === width && bitmap.height === height) {
            g.drawImage(bitmap, 0, 0);
            return;
        }
        const scale = Math.min(width / bitmap.width, height / bitmap.height);
        const w = bitmap.width * scale, h = bitmap.height * scale;
        g.drawImage(bitmap, (width - w) / 2, (height - h) / 2, w, h);
    }

    function drawSide(kind, x, w) {
        if (w <= 0) return;
        ctx.save();
        ctx.beginPath();
        ctx.rect(x, 0, w, height);
        ctx.clip();
        drawFitted(ctx, bitmaps[kind]);
        ctx.restore();
    }

    // Sizes the canvas on screen: the whole image in the space left, integer upscaling of small films.
    function layout() {
        if (!width) return;
        const main = $('main');
        const availW = Math.max(16, main.clientWidth - 12), availH = Math.max(16, main.clientHeight - 12);
        let scale = Math.min(availW / width, availH / height);
        if (scale >= 1) scale = Math.floor(scale);
        canvas.style.width = Math.max(1, Math.round(width * scale)) + 'px';
        canvas.style.height = Math.max(1, Math.round(height * scale)) + 'px';
        updateDisplay();
    }

    function updateDisplay() {
        if (!divider) return;
        divider.style.left = (split * 100) + '%';
        document.body.classList.toggle('heatmap', !!settings.heatmap);
        $('left-label').textContent = settings.left || '';
        $('right-label').textContent = settings.right || '';
        if (Number.isFinite(Number(settings.exposure))) {
            $('exposure-value').textContent = Number(settings.exposure).toFixed(1) + ' EV';
        }
        updateSaveLink();
    }

    function updateSaveLink() {
        const side = $('save-side').value === 'right' ? 'right' : 'left';
        $('save-exr').href = 'save.exr?' + tokenQuery + '&side=' + side;
    }

    // ---------------------------------------------------------------- status line
    const isRaster = (method) => typeof method === 'string' && (method.startsWith('raster') || method === 'baked');

    function fpsOf(kind, now) {
        const times = frameTimes[kind];
        while (times.length && now - times[0] > FPS_WINDOW_MS) times.shift();
        return times.length * 1000 / FPS_WINDOW_MS;
    }

    function updateRates() {
        const now = performance.now();
        stats.fpsLeft = fpsOf(KIND_LEFT, now);
        stats.fpsRight = fpsOf(KIND_RIGHT, now);
        stats.fpsHeatmap = fpsOf(KIND_HEATMAP, now);
        const raster = [];
        if (isRaster(settings.left)) raster.push(stats.fpsLeft);
        if (isRaster(settings.right)) raster.push(stats.fpsRight);
        stats.fps = raster.length ? Math.max(...raster) : stats.fpsLeft + stats.fpsRight + stats.fpsHeatmap;
        renderStatus();
    }

    function formatNumber(v) {
        if (typeof v !== 'number' || !Number.isFinite(v)) return '\u2014';
        const a = Math.abs(v);
        if (a !== 0 && (a < 1e-3 || a >= 1e6)) return v.toExponential(3);
        return String(Number(v.toPrecision(4)));
    }

    function formatRate(v) {
        if (!Number.isFinite(v)) return '\u2014';
        if (v >= 1e6) return (v / 1e6).toFixed(2) + ' M';
        if (v >= 1e3) return (v / 1e3).toFixed(1) + ' k';
        return v.toFixed(0) + ' ';
    }

    function sideText(name, s) {
        if (!s) return name + ': \u2014';
        let text = name + ': ' + s.method + ' \u00b7 ' + s.spp + ' spp \u00b7 ' +
            (Number.isFinite(s.seconds) ? s.seconds.toFixed(1) : '\u2014') + ' s \u00b7 ' +
            formatRate(s.samples_per_second) + 'samples/s';
        if (s.done) text += ' \u00b7 done';
        const fps = name === 'left' ? stats.fpsLeft : stats.fpsRight;
        if (isRaster(s.method)) text += ' \u00b7 ' + fps.toFixed(0) + ' frames/s';
        return text;
    }

    function renderStatus() {
        if (!statusEl) return;
        const st = window.candelaStatus;
        const lines = [];
        if (st) lines.push(sideText('left', st.left) + '    ' + sideText('right', st.right));
        let line = 'received ' + stats.fps.toFixed(0) + ' frames/s';
        line += ' \u00b7 latency ' + (stats.latencyMs === null ? '\u2014' : stats.latencyMs.toFixed(0) + ' ms');
        line += ' \u00b7 ' + (stats.lastFrameBytes / 1024).toFixed(1) + ' kB/frame';
        if (!stats.connected) line += ' \u00b7 disconnected';
        lines.push(line);
        statusEl.textContent = lines.join('\n');
    }

    // ---------------------------------------------------------------- sending (once per animation frame)
    function queueSettings(s) {
        const now = performance.now();
        for (const key of Object.keys(s)) localEditAt[key] = now;
        Object.assign(settings, s);
        pendingSettings = Object.assign(pendingSettings || {}, s);
        updateDisplay();
        needsDraw = true;
    }

    function flush() {
        if (pendingSettings && stats.connected) {
            if (send(Object.assign({type: 'settings'}, pendingSettings))) stats.settingsMessagesSent++;
            pendingSettings = null;
        }
        if (cameraDirty && camera && stats.connected) {
            // Ids increase with every message, and start above any id the server applied before
            // (another page's, or this page's before a reload), so that an echo is unambiguous.
            const id = Math.max(stats.lastCameraId, highestFrameCameraId) + 1;
            if (send({type: 'camera', id, origin: camera.origin, target: camera.target, up: camera.up, fov: camera.fov})) {
                stats.lastCameraId = id;
                stats.cameraMessagesSent++;
                cameraSentAt.set(id, performance.now());
                if (cameraSentAt.size > 1000) cameraSentAt.delete(cameraSentAt.keys().next().value);
            }
            cameraDirty = false;
        }
    }

    function tick(now) {
        const dt = Math.min(0.1, Math.max(0, (now - lastTick) / 1000));
        lastTick = now;
        fly(dt);
        flush();
        if (needsDraw) draw();
        requestAnimationFrame(tick);
    }

    // ---------------------------------------------------------------- camera motion
    function cameraChanged() {
        cameraDirty = true;
    }

    function frame() {
        const forward = normalize(sub(camera.target, camera.origin));
        let right = cross(forward, worldUp);
        if (length(right) < 1e-6) right = cross(forward, Math.abs(forward[0]) < 0.9 ? [1, 0, 0] : [0, 0, 1]);
        right = normalize(right);
        const up = cross(right, forward);
        return {forward, right, up};
    }

    // Orbit around the target: dx, dy in CSS pixels of the canvas.
    function orbit(dx, dy) {
        if (!camera) return;
        const w = canvas.clientWidth || width || 1;
        const yaw = -dx / w * Math.PI, pitch = -dy / w * Math.PI;
        let offset = sub(camera.origin, camera.target);
        const r = length(offset);
        if (r <= 0) return;
        offset = rotate(offset, worldUp, yaw);
        // Pitch about the camera's right axis, keeping away from the poles.
        // A positive rotation about up x offset moves the origin away from up (the angle grows);
        // dragging down (pitch < 0) raises the camera.
        const angle = Math.acos(Math.max(-1, Math.min(1, dot(normalize(offset), worldUp))));
        const limit = 0.02;
        const delta = Math.max(limit - angle, Math.min(Math.PI - limit - angle, pitch));
        const axis = normalize(cross(worldUp, offset));
        if (length(axis) > 0) offset = rotate(offset, axis, delta);
        camera.origin = add(camera.target, offset);
        cameraChanged();
    }

    // Pan: move origin and target in the image plane so the scene follows the mouse.
    function pan(dx, dy) {
        if (!camera) return;
        const {right, up} = frame();
        const dist = length(sub(camera.target, camera.origin));
        const w = canvas.clientWidth || width || 1;
        const perPixel = 2 * dist * Math.tan(camera.fov * Math.PI / 360) / w;
        const move = add(mul(right, -dx * perPixel), mul(up, dy * perPixel));
        camera.origin = add(camera.origin, move);
        camera.target = add(camera.target, move);
        cameraChanged();
    }

    // Dolly toward (amount < 0) or away from the target, by a factor exp(amount).
    function dolly(amount) {
        if (!camera) return;
        const offset = sub(camera.origin, camera.target);
        const dist = length(offset);
        if (dist <= 0) return;
        const next = Math.max(sceneSize * 1e-3, Math.min(sceneSize * 100, dist * Math.exp(amount)));
        camera.origin = add(camera.target, mul(offset, next / dist));
        cameraChanged();
    }

    function fly(dt) {
        if (!camera || keys.size === 0 || dt <= 0) return;
        const {forward, right} = frame();
        let move = [0, 0, 0];
        if (keys.has('w')) move = add(move, forward);
        if (keys.has('s')) move = sub(move, forward);
        if (keys.has('d')) move = add(move, right);
        if (keys.has('a')) move = sub(move, right);
        if (keys.has('e')) move = add(move, worldUp);
        if (keys.has('q')) move = sub(move, worldUp);
        if (length(move) === 0) return;
        const speed = sceneSize * 0.5 * (keys.has('shift') ? 4 : 1);
        move = mul(normalize(move), speed * dt);
        camera.origin = add(camera.origin, move);
        camera.target = add(camera.target, move);
        cameraChanged();
    }

    // ---------------------------------------------------------------- input
    let press = null;          // the pointer press on the canvas
    let dividerDrag = false;

    function imagePixel(event) {
        const rect = canvas.getBoundingClientRect();
        const x = Math.floor((event.clientX - rect.left) * width / rect.width);
        const y = Math.floor((event.clientY - rect.top) * height / rect.height);
        return {x: Math.max(0, Math.min(width - 1, x)), y: Math.max(0, Math.min(height - 1, y))};
    }

    function bindInput() {
        canvas.addEventListener('contextmenu', (e) => e.preventDefault());
        canvas.addEventListener('pointerdown', (e) => {
            if (press) return;
            canvas.focus();
            press = {id: e.pointerId, button: e.button, shift: e.shiftKey, x0: e.clientX, y0: e.clientY,
                     x: e.clientX, y: e.clientY, moved: false};
            canvas.setPointerCapture(e.pointerId);
            e.preventDefault();
        });
        canvas.addEventListener('pointermove', (e) => {
            if (!press || e.pointerId !== press.id) return;
            if (!press.moved && Math.hypot(e.clientX - press.x0, e.clientY - press.y0) > CLICK_SLOP) {
                press.moved = true;
                canvas.classList.add('dragging');
            }
            if (!press.moved) return;
            const dx = e.clientX - press.x, dy = e.clientY - press.y;
            press.x = e.clientX;
            press.y = e.clientY;
            if (press.button === 2 || press.button === 1 || (press.button === 0 && (press.shift || e.shiftKey))) pan(dx, dy);
            else if (press.button === 0) orbit(dx, dy);
        });
        const end = (e) => {
            if (!press || e.pointerId !== press.id) return;
            const wasClick = !press.moved && press.button === 0 && e.type === 'pointerup';
            press = null;
            canvas.classList.remove('dragging');
            if (wasClick && width) {
                const p = imagePixel(e);
                const side = settings.heatmap ? 'left' : (p.x < Math.round(split * width) ? 'left' : 'right');
                inspectorEl.textContent = 'Inspecting ' + side + ' pixel (' + p.x + ', ' + p.y + ')\u2026';
                send({type: 'inspect', x: p.x, y: p.y, side});
            }
        };
        canvas.addEventListener('pointerup', end);
        canvas.addEventListener('pointercancel', end);
        canvas.addEventListener('wheel', (e) => {
            e.preventDefault();
            const unit = e.deltaMode === 1 ? 16 : (e.deltaMode === 2 ? 400 : 1);
            dolly(e.deltaY * unit * 0.0015);
        }, {passive: false});

        window.addEventListener('keydown', (e) => {
            const tag = (e.target && e.target.tagName) || '';
            if (tag === 'INPUT' || tag === 'SELECT' || tag === 'TEXTAREA' || e.ctrlKey || e.metaKey || e.altKey) return;
            const k = e.key.toLowerCase();
            if ('wasdqe'.includes(k) && k.length === 1) {
                keys.add(k);
                e.preventDefault();
            }
            if (e.shiftKey) keys.add('shift');
        });
        window.addEventListener('keyup', (e) => {
            keys.delete(e.key.toLowerCase());
            if (!e.shiftKey) keys.delete('shift');
        });
        window.addEventListener('blur', () => keys.clear());

        // The divider.
        divider.addEventListener('pointerdown', (e) => {
            dividerDrag = true;
            divider.setPointerCapture(e.pointerId);
            e.preventDefault();
        });
        divider.addEventListener('pointermove', (e) => {
            if (!dividerDrag) return;
            const rect = canvas.getBoundingClientRect();
            setSplit((e.clientX - rect.left) / rect.width);
        });
        const endDivider = () => { dividerDrag = false; };
        divider.addEventListener('pointerup', endDivider);
        divider.addEventListener('pointercancel', endDivider);

        // Settings controls.
        const bindSelect = (key, parse) => controls[key].addEventListener('change', () => {
            queueSettings({[key]: parse(controls[key].value)});
        });
        bindSelect('left', String);
        bindSelect('right', String);
        bindSelect('shading', String);
        bindSelect('reflection', String);
        bindSelect('shadows', String);
        bindSelect('aa', (v) => parseInt(v, 10));
        bindSelect('gi', String);
        bindSelect('tonemap', String);
        controls.exposure.addEventListener('input', () => queueSettings({exposure: parseFloat(controls.exposure.value)}));
        controls.heatmap.addEventListener('change', () => queueSettings({heatmap: controls.heatmap.checked}));
        $('save-side').addEventListener('change', updateSaveLink);
        $('save-png').addEventListener('click', savePng);
        window.addEventListener('resize', layout);
    }

    function setSplit(value) {
        if (!Number.isFinite(value)) return;
        split = Math.min(1, Math.max(0, value));
        queueSettings({split});
    }

    function savePng() {
        canvas.toBlob((blob) => {
            if (!blob) return;
            const url = URL.createObjectURL(blob);
            const a = document.createElement('a');
            a.href = url;
            a.download = 'candela-view.png';
            document.body.appendChild(a);
            a.click();
            a.remove();
            setTimeout(() => URL.revokeObjectURL(url), 10000);
        }, 'image/png');
    }

    // ---------------------------------------------------------------- start
    function start() {
        canvas = $('view');
        ctx = canvas.getContext('2d');
        stage = $('stage');
        divider = $('divider');
        statusEl = $('status');
        inspectorEl = $('inspector');
        connectionEl = $('connection');
        messagesEl = $('messages');
        controls.left = $('left-method');
        controls.right = $('right-method');
        for (const key of ['shading', 'reflection', 'shadows', 'aa', 'gi', 'exposure', 'tonemap', 'heatmap']) controls[key] = $(key);
        bindInput();
        updateDisplay();
        setInterval(updateRates, 250);
        requestAnimationFrame(tick);
        showConnection('Connecting\u2026');
        connect();
    }

    // For tests and the console: the state, and the actions the mouse and keyboard take.
    window.candela = {
        get scene() { return scene; },
        get camera() { return camera ? JSON.parse(JSON.stringify(camera)) : null; },
        get settings() { return Object.assign({}, settings); },
        get split() { return split; },
        // A decoded frame waits for the next animation frame to be drawn: the canvas does not show
        // it yet (tests read the canvas and the frames only when nothing is pending).
        get drawPending() { return needsDraw; },
        send,
        setCamera(c) { setCameraFields(c); cameraChanged(); },
        setSettings(s) { queueSettings(s); applySettings(s, false); },
        setSplit,
        orbit, pan, dolly,
        // The newest decoded frame of a kind (0 left, 1 right, 2 heatmap) as drawn over the film
        // (RGBA bytes, width x height) with the frame's own size, or null.
        frameData(kind) {
            const bitmap = bitmaps[kind];
            if (!bitmap) return null;
            const c = document.createElement('canvas');
            c.width = width;
            c.height = height;
            const g = c.getContext('2d');
            drawFitted(g, bitmap);
            return {seq: bitmapMeta[kind].seq, cameraId: bitmapMeta[kind].cameraId, width, height,
                    frameWidth: bitmap.width, frameHeight: bitmap.height,
                    data: g.getImageData(0, 0, width, height).data};
        },
    };

    if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
    else start();
})();
