// omnicloud serve, live walking: the page sends its pose over a WebSocket (/api/live) as the
// person moves (keys, drag, touch, a gamepad, XR thumbsticks) and shows the ODS pairs the
// server streams back (a 4-byte little-endian header length, a JSON header, a JPEG). The
// server renders only the newest pose, so poses are sent freely while moving. The protocol is
// described in docs/LIVE.md.
'use strict';

(() => {
  const $ = (id) => document.getElementById(id);
  const viewer = window.viewer;
  const live = window.live;

  const walk = {
    x: 0, y: 0,          // file coordinates of the pose
    height: null,        // metres above the ground once Q/E changed it, else the server's
    seq: 0,              // the newest pose's number
    shownSeq: 0,         // the number of the frame on screen
    last: null,          // the header of the frame on screen
    frames: 0,           // frames shown
    fps: 0,
    moving: false,
    socket: null,
    error: null,
  };
  window.walk = walk;

  const keys = new Set();
  const WALK_KEYS = new Set(['w', 'a', 's', 'd', 'q', 'e', 'ArrowUp', 'ArrowDown', 'ArrowLeft',
    'ArrowRight']);
  const TURN_RATE = 90;    // degrees a second, arrows and smooth stick turning
  const SNAP = 30;         // degrees a snap turn
  const SEND_EVERY = 33;   // milliseconds between poses while moving
  let touchWalk = 0;       // fingers on the canvas beyond the first
  let snapArmed = true;    // a snap turn needs the stick back to centre before the next
  let xrAxes = { move: [0, 0], turn: 0, head: 0 };
  let lastSent = 0;
  let unsent = false;      // moved since the last pose sent
  let shownTimes = [];

  const perMetre = () => 1 / ((live.scan && live.scan.metres_per_unit) || 1);
  const heading = () => {
    const xrYaw = viewer.xrYaw();
    return xrYaw === null ? viewer.view().yaw : xrYaw + xrAxes.head;
  };

  // ---- the stream ----

  function connect() {
    const socket = new WebSocket(`ws://${location.host}/api/live`);
    socket.binaryType = 'arraybuffer';
    walk.socket = socket;
    socket.addEventListener('message', (e) => {
      if (typeof e.data === 'string') {
        walk.error = JSON.parse(e.data).error;
        $('status').textContent = `live: ${walk.error}`;
        return;
      }
      show(e.data).catch((err) => { walk.error = String(err); });
    });
    socket.addEventListener('close', (e) => {
      walk.socket = null;
      if (e.code !== 1000 && e.code !== 1001) {
        walk.error = `the live stream closed: ${e.code} ${e.reason}`;
        $('status').textContent = walk.error;
      }
    });
    return new Promise((resolve, reject) => {
      socket.addEventListener('open', resolve);
      socket.addEventListener('error', () => reject(new Error('the live stream did not open')));
    });
  }

  async function show(buffer) {
    const len = new DataView(buffer).getUint32(0, true);
    const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, len)));
    const blob = new Blob([new Uint8Array(buffer, 4 + len)], { type: 'image/jpeg' });
    const options = { colorSpaceConversion: 'none', premultiplyAlpha: 'none', imageOrientation: 'none' };
    if (header.width > viewer.maxTexture) {
      options.resizeWidth = viewer.maxTexture;
      options.resizeHeight = viewer.maxTexture;
      options.resizeQuality = 'high';
    }
    const image = await createImageBitmap(blob, options);
    if (header.seq < walk.shownSeq) return;
    walk.shownSeq = header.seq;
    walk.last = header;
    walk.frames += 1;
    const now = performance.now();
    shownTimes = shownTimes.filter((t) => now - t < 1000);
    shownTimes.push(now);
    walk.fps = shownTimes.length;
    await viewer.showImage(image, 'ods');
    const [x, y, z] = header.camera;
    $('walk').textContent = `${x.toFixed(1)}, ${y.toFixed(1)}, ${z.toFixed(1)} · heading ` +
      `${((heading() % 360 + 360) % 360).toFixed(0)}° · ${walk.fps} fps` +
      (header.still ? ' · still' : '');
    $('timing').textContent =
      `render ${header.render_ms.toFixed(0)} ms, encode ${header.encode_ms.toFixed(0)} ms`;
    live.camera = [x, y];
  }

  function sendPose() {
    if (!walk.socket || walk.socket.readyState !== WebSocket.OPEN) return;
    walk.seq += 1;
    const pose = { seq: walk.seq, x: walk.x, y: walk.y, yaw: heading(),
      pitch: viewer.view().pitch, ipd: Number($('ipd').value) };
    if (walk.height !== null) pose.height = walk.height;
    walk.socket.send(JSON.stringify(pose));
    lastSent = performance.now();
    unsent = false;
    placeHeading();
  }

  // ---- the map: where you are and which way you face; the link to this view ----

  function placeHeading() {
    const grid = live.scan.map;
    const arrow = $('heading');
    arrow.style.left = `${(walk.x - grid.x0) / grid.pixel / grid.width * 100}%`;
    arrow.style.top = `${(grid.y1 - walk.y) / grid.pixel / grid.height * 100}%`;
    arrow.style.transform = `rotate(${heading()}deg)`;
    arrow.hidden = false;
    const query = new URLSearchParams({ x: walk.x.toFixed(2), y: walk.y.toFixed(2),
      yaw: (((heading() % 360) + 360) % 360).toFixed(1) });
    $('link').href = `?${query}`;
  }

  // ---- moving ----

  const axis = (v) => (Math.abs(v) < 0.15 ? 0 : v);

  function controls() {
    const held = (...names) => names.some((n) => keys.has(n));
    let forward = (held('w', 'ArrowUp') ? 1 : 0) - (held('s', 'ArrowDown') ? 1 : 0);
    let side = (held('d') ? 1 : 0) - (held('a') ? 1 : 0);
    let turn = (held('ArrowRight') ? 1 : 0) - (held('ArrowLeft') ? 1 : 0);
    const up = (held('e') ? 1 : 0) - (held('q') ? 1 : 0);
    if (touchWalk > 0) forward += 1;
    let stick = 0;
    for (const pad of navigator.getGamepads ? navigator.getGamepads() : []) {
      if (!pad) continue;
      side += axis(pad.axes[0] || 0);
      forward -= axis(pad.axes[1] || 0);
      stick += axis(pad.axes[2] || 0);
    }
    side += axis(xrAxes.move[0]);
    forward -= axis(xrAxes.move[1]);
    stick += axis(xrAxes.turn);
    return { forward, side, turn, stick, up };
  }

  let lastTick = performance.now();
  function tick(now) {
    const dt = Math.min(0.1, (now - lastTick) / 1000);
    lastTick = now;
    const c = controls();
    const snap = $('snap-turn').checked;
    let turned = c.turn * TURN_RATE * dt;
    if (snap && c.stick !== 0) {
      if (snapArmed && Math.abs(c.stick) > 0.7) {
        turned += Math.sign(c.stick) * SNAP;
        snapArmed = false;
      }
    } else {
      turned += c.stick * TURN_RATE * dt;
    }
    if (Math.abs(c.stick) < 0.3) snapArmed = true;
    if (turned !== 0) {
      if (viewer.xrYaw() !== null) viewer.turnXR(turned);
      else {
        const v = viewer.view();
        viewer.setView(v.yaw + turned, v.pitch, v.fov);
      }
    }
    const speed = Number($('speed').value) * perMetre() * dt;
    const h = heading() * Math.PI / 180;
    const dx = (c.forward * Math.sin(h) + c.side * Math.cos(h)) * speed;
    const dy = (c.forward * Math.cos(h) - c.side * Math.sin(h)) * speed;
    const { lo, hi } = bounds();
    const moved = dx !== 0 || dy !== 0 || c.up !== 0 || turned !== 0;
    walk.x = Math.min(hi[0], Math.max(lo[0], walk.x + dx));
    walk.y = Math.min(hi[1], Math.max(lo[1], walk.y + dy));
    if (c.up !== 0) {
      const base = walk.height === null ? live.scan.height / perMetre() : walk.height;
      walk.height = Math.min(1000, Math.max(0, base + c.up * dt));
    }
    walk.moving = moved;
    if (moved) unsent = true;
    $('vignette').hidden = !(moved && $('vignette-on').checked);
    // While moving at most every SEND_EVERY ms; on stopping, where it stopped.
    if (unsent && (!moved || now - lastSent >= SEND_EVERY)) sendPose();
    requestAnimationFrame(tick);
  }

  const bounds = () => ({ lo: live.scan.min, hi: live.scan.max });

  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;
    const key = e.key.length === 1 ? e.key.toLowerCase() : e.key;
    if (!WALK_KEYS.has(key)) return;
    keys.add(key);
    // The viewer's own arrow keys look around; here they walk and turn.
    e.stopImmediatePropagation();
    e.preventDefault();
  }, true);
  window.addEventListener('keyup', (e) => {
    keys.delete(e.key.length === 1 ? e.key.toLowerCase() : e.key);
  }, true);
  window.addEventListener('blur', () => keys.clear());
  const canvas = $('view');
  canvas.addEventListener('touchstart', (e) => { touchWalk = e.touches.length - 1; });
  canvas.addEventListener('touchend', (e) => { touchWalk = e.touches.length - 1; });
  canvas.addEventListener('touchcancel', () => { touchWalk = 0; });
  // Dragging turns the view (the viewer's): the map's arrow and the next pose follow.
  canvas.addEventListener('pointerup', () => sendPose());

  // In VR: the left stick walks, the right one turns; forward is where the head looks.
  viewer.onXRFrame = (frame, session, pose) => {
    // The head's orientation (a runtime without a viewer transform: the first eye's).
    const o = (pose.transform || pose.views[0].transform).orientation;
    // Yaw of the head about the vertical (y) axis, clockwise seen from above.
    xrAxes.head = -Math.atan2(2 * (o.w * o.y + o.x * o.z), 1 - 2 * (o.y * o.y + o.x * o.x)) * 180 / Math.PI;
    xrAxes.move = [0, 0];
    xrAxes.turn = 0;
    for (const source of session.inputSources || []) {
      const axes = (source.gamepad && source.gamepad.axes) || [];
      // xr-standard mapping: the thumbstick is axes 2 and 3.
      const [sx, sy] = axes.length >= 4 ? [axes[2], axes[3]] : [axes[0] || 0, axes[1] || 0];
      if (source.handedness === 'right') xrAxes.turn = sx;
      else xrAxes.move = [sx, sy];
    }
  };

  $('speed').addEventListener('input', () => {
    $('speed-value').textContent = Number($('speed').value).toFixed(1);
  });
  $('map').addEventListener('click', (e) => {
    const box = $('map').getBoundingClientRect();
    const grid = live.scan.map;
    walk.x = grid.x0 + (e.clientX - box.left) / box.width * grid.width * grid.pixel;
    walk.y = grid.y1 - (e.clientY - box.top) / box.height * grid.height * grid.pixel;
    placeHeading();
  });

  // Walks to file (x, y) facing `yaw` degrees and settles with the header of its frame.
  walk.standAt = (x, y, yaw) => {
    walk.x = Number(x);
    walk.y = Number(y);
    const v = viewer.view();
    viewer.setView(Number(yaw), v.pitch, v.fov);
    sendPose();
    const seq = walk.seq;
    return new Promise((resolve) => {
      const wait = () => (walk.shownSeq >= seq ? resolve(walk.last) : setTimeout(wait, 10));
      wait();
    });
  };

  async function start() {
    await live.ready;
    [walk.x, walk.y] = live.scan.camera;
    await connect();
    const params = new URLSearchParams(location.search);
    requestAnimationFrame(tick);
    if (params.has('x') && params.has('y')) {
      await walk.standAt(params.get('x'), params.get('y'), params.get('yaw') || 0);
    } else {
      placeHeading();
    }
  }

  walk.ready = start().catch((e) => {
    walk.error = String(e.message || e);
    $('status').textContent = `live: ${walk.error}`;
    throw e;
  });
})();
