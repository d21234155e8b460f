// omnicloud view: shows an equirectangular panorama (mono, or ODS with the left eye on top)
// by casting a ray per pixel and looking its direction up in the image. No sphere mesh, so
// no seam and no pole pinch. Directions follow DESIGN.md: longitude 0 at the image centre
// (the heading), +90 degrees to the right; latitude +90 on the top row.
//
// An MP4 (`/video`) plays through a <video> element whose current frame is uploaded as the
// texture each time it changes; the frame slider seeks it to the middle of frame N.
//
// A folder of a survey's stations (/api/info lists them) gets a list and a top-down map of
// the stations; picking one shows its frame.
//
// Space of the rays: x right, y up, -z forward (WebXR's reference space), so for a
// panorama direction d: longitude = atan2(d.x, -d.z), latitude = asin(d.y).
'use strict';

(() => {
  const $ = (id) => document.getElementById(id);
  const canvas = $('view');
  const statusLine = $('status');

  const VERTEX = `#version 300 es
    // One triangle that covers the viewport; the fragment gets its normalized device coords.
    const vec2 CORNERS[3] = vec2[3](vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0));
    out vec2 v_ndc;
    void main() {
      v_ndc = CORNERS[gl_VertexID];
      gl_Position = vec4(v_ndc, 0.0, 1.0);
    }`;

  const FRAGMENT = `#version 300 es
    precision highp float;
    in vec2 v_ndc;
    uniform sampler2D u_pano;
    uniform mat4 u_inv_proj;  // clip space -> view space
    uniform mat3 u_rot;       // view space -> panorama space
    uniform int u_ods;        // 1: top half left eye, bottom half right eye
    uniform int u_mode;       // 0 left eye (or mono), 1 right eye, 2 anaglyph
    uniform float u_height;   // texture height in texels
    out vec4 colour;
    const float PI = 3.141592653589793;

    // The eye's colour along direction d, composited over black by its alpha (coverage).
    vec3 look(vec3 d, int eye) {
      float lon = atan(d.x, -d.z);
      float lat = asin(clamp(d.y, -1.0, 1.0));
      float u = lon / (2.0 * PI) + 0.5;
      float v = 0.5 - lat / PI;
      if (u_ods == 1) {
        // Stay half a texel inside the eye's half so filtering never mixes the eyes.
        float half_texel = 0.5 / u_height;
        v = clamp(0.5 * v, half_texel, 0.5 - half_texel) + 0.5 * float(eye);
      }
      vec4 c = texture(u_pano, vec2(u, v));
      return c.rgb * c.a;
    }

    vec3 to_linear(vec3 c) {
      return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(0.04045, c));
    }
    vec3 to_srgb(vec3 c) {
      return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
    }

    void main() {
      vec4 p = u_inv_proj * vec4(v_ndc, -1.0, 1.0);
      vec3 d = normalize(u_rot * (p.xyz / p.w));
      if (u_ods == 1 && u_mode == 2) {
        // Half-colour anaglyph, as omnicloud render --anaglyph mixes it (in linear light):
        // red = Rec. 709 luminance of the left eye, green and blue = the right eye's.
        vec3 l = to_linear(look(d, 0));
        vec3 r = to_linear(look(d, 1));
        colour = vec4(to_srgb(vec3(dot(l, vec3(0.2126, 0.7152, 0.0722)), r.g, r.b)), 1.0);
      } else {
        colour = vec4(look(d, u_mode == 1 ? 1 : 0), 1.0);
      }
    }`;

  // ---- small matrix helpers (column-major, as WebGL wants them) ----

  const RAD = Math.PI / 180;

  function mul3(a, b) {
    const c = new Float32Array(9);
    for (let col = 0; col < 3; col++) {
      for (let row = 0; row < 3; row++) {
        let s = 0;
        for (let k = 0; k < 3; k++) s += a[k * 3 + row] * b[col * 3 + k];
        c[col * 3 + row] = s;
      }
    }
    return c;
  }

  // Turns about +y by `deg`; a positive angle turns -z (forward) towards -x (left).
  function rotY(deg) {
    const c = Math.cos(deg * RAD), s = Math.sin(deg * RAD);
    return new Float32Array([c, 0, -s, 0, 1, 0, s, 0, c]);
  }

  // Turns about +x by `deg`; a positive angle turns -z (forward) towards +y (up).
  function rotX(deg) {
    const c = Math.cos(deg * RAD), s = Math.sin(deg * RAD);
    return new Float32Array([1, 0, 0, 0, c, s, 0, -s, c]);
  }

  function quatToMat3(q) {
    const { x, y, z, w } = q;
    return new Float32Array([
      1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y),
      2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x),
      2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y),
    ]);
  }

  function invert4(m) {
    const inv = new Float32Array(16);
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] + m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] + m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] - m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] + m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    const det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    for (let i = 0; i < 16; i++) inv[i] /= det;
    return inv;
  }

  // The inverse of a symmetric perspective with vertical field of view `fovDeg`: maps a
  // point of the near plane (ndc x, y, -1) to the view-space ray (x a f, y f, -1).
  function inversePerspective(fovDeg, aspect) {
    const f = Math.tan(fovDeg * RAD / 2);
    return new Float32Array([aspect * f, 0, 0, 0, 0, f, 0, 0, 0, 0, 0, 0, 0, 0, -1, 1]);
  }

  // ---- WebGL2 set-up ----

  const gl = canvas.getContext('webgl2', {
    alpha: false, antialias: false, depth: false, preserveDrawingBuffer: true,
  });

  function fail(message) {
    statusLine.textContent = message;
    viewer.error = message;
    throw new Error(message);
  }

  const viewer = {
    error: null,
    info: null,
    xrFrames: 0,
    xrViews: [],
  };
  window.viewer = viewer;

  if (!gl) fail('WebGL2 is not available in this browser.');

  function compile(type, source) {
    const s = gl.createShader(type);
    gl.shaderSource(s, source);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) fail('shader: ' + gl.getShaderInfoLog(s));
    return s;
  }
  const program = gl.createProgram();
  gl.attachShader(program, compile(gl.VERTEX_SHADER, VERTEX));
  gl.attachShader(program, compile(gl.FRAGMENT_SHADER, FRAGMENT));
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) fail('link: ' + gl.getProgramInfoLog(program));
  const loc = {};
  for (const name of ['u_pano', 'u_inv_proj', 'u_rot', 'u_ods', 'u_mode', 'u_height']) {
    loc[name] = gl.getUniformLocation(program, name);
  }
  gl.bindVertexArray(gl.createVertexArray());

  const texture = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, texture);
  // No mipmaps: the longitude jumps from 1 to 0 at the seam, and a mip level chosen from
  // that jump would draw a line there. Repeat across the seam, clamp at the poles.
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.REPEAT);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  let textureHeight = 1;

  // ---- view state ----

  const MODES = { mono: 0, left: 0, right: 1, anaglyph: 2 };
  const state = { yaw: 0, pitch: 0, fov: 90, mode: 'mono', frame: 0 };
  let xr = null;

  function clampView() {
    state.pitch = Math.max(-90, Math.min(90, state.pitch));
    state.fov = Math.max(10, Math.min(120, state.fov));
    state.yaw = ((state.yaw + 180) % 360 + 360) % 360 - 180;
  }

  function drawView(invProj, rot, mode) {
    gl.useProgram(program);
    gl.uniform1i(loc.u_pano, 0);
    gl.uniformMatrix4fv(loc.u_inv_proj, false, invProj);
    gl.uniformMatrix3fv(loc.u_rot, false, rot);
    gl.uniform1i(loc.u_ods, viewer.info && viewer.info.kind === 'ods' ? 1 : 0);
    gl.uniform1i(loc.u_mode, mode);
    gl.uniform1f(loc.u_height, textureHeight);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }

  let drawPending = false;
  let afterDraw = [];
  function drawScreen() {
    drawPending = false;
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(canvas.clientWidth * dpr));
    const h = Math.max(1, Math.round(canvas.clientHeight * dpr));
    if (canvas.width !== w || canvas.height !== h) {
      canvas.width = w;
      canvas.height = h;
    }
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, w, h);
    drawView(inversePerspective(state.fov, w / h), mul3(rotY(-state.yaw), rotX(state.pitch)),
      MODES[state.mode]);
    $('readout').textContent =
      `yaw ${state.yaw.toFixed(1)}°  pitch ${state.pitch.toFixed(1)}°  fov ${state.fov.toFixed(0)}°`;
    const waiting = afterDraw;
    afterDraw = [];
    // One more frame so the drawn one has reached the screen (and a screenshot).
    requestAnimationFrame(() => waiting.forEach((resolve) => resolve()));
  }

  // Schedules a redraw; the promise settles once it is on screen.
  function requestDraw() {
    // In VR the headset's frame loop draws; there is no flat view to wait for.
    if (xr) return Promise.resolve();
    const done = new Promise((resolve) => afterDraw.push(resolve));
    if (!drawPending) {
      drawPending = true;
      requestAnimationFrame(drawScreen);
    }
    return done;
  }

  // ---- frames ----

  const bitmaps = new Map();  // frame -> Promise<ImageBitmap>, a few around the current one
  const KEEP = 8;
  let maxTexture = gl.getParameter(gl.MAX_TEXTURE_SIZE);

  async function fetchBitmap(n) {
    const response = await fetch(`/frames/${n}`);
    if (!response.ok) throw new Error(`frame ${n}: ${response.status} ${await response.text()}`);
    const blob = await response.blob();
    const { width, height } = viewer.info;
    const scale = Math.min(1, maxTexture / width, maxTexture / height);
    // Raw bytes: no colour-space conversion, no premultiplication (alpha is coverage).
    const options = { colorSpaceConversion: 'none', premultiplyAlpha: 'none', imageOrientation: 'none' };
    if (scale < 1) {
      options.resizeWidth = Math.floor(width * scale);
      options.resizeHeight = Math.floor(height * scale);
      options.resizeQuality = 'high';
    }
    return createImageBitmap(blob, options);
  }

  function bitmap(n) {
    if (!bitmaps.has(n)) {
      bitmaps.set(n, fetchBitmap(n));
      while (bitmaps.size > KEEP) bitmaps.delete(bitmaps.keys().next().value);
    }
    return bitmaps.get(n);
  }

  let showing = 0;  // the latest frame request wins

  // ---- video ----

  let video = null;  // the <video> element when the panorama is an MP4

  // Loads /video into a muted, inline <video> (muted: browsers let it play without a click).
  function openVideo() {
    video = document.createElement('video');
    video.muted = true;
    video.playsInline = true;
    video.preload = 'auto';
    video.loop = true;
    const loaded = new Promise((resolve, reject) => {
      video.addEventListener('loadeddata', resolve, { once: true });
      video.addEventListener('error', () => {
        const e = video.error;
        reject(new Error(`/video: the browser cannot play it (${e ? e.message || 'code ' + e.code : 'error'})`));
      }, { once: true });
    });
    video.src = '/video';
    return loaded;
  }

  function uploadVideo() {
    gl.bindTexture(gl.TEXTURE_2D, texture);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, video);
    textureHeight = video.videoHeight;
  }

  // The frame on show at the video's current time.
  function videoFrame() {
    const { frames, fps } = viewer.info.video;
    return Math.max(0, Math.min(frames - 1, Math.floor(video.currentTime * fps + 1e-6)));
  }

  function showSlider(n) {
    state.frame = n;
    $('frame').value = String(n);
    $('frame-label').textContent = `${n + 1} / ${viewer.info.frames}`;
  }

  // Seeks to the middle of frame n; settles once that frame can be drawn. `seeked` can fire
  // before the new frame reaches the compositor (a loaded machine uploads the old one), so
  // where the browser reports presented frames the seek also waits for one, or a short while.
  function seekVideo(n) {
    const presented = video.requestVideoFrameCallback
      ? new Promise((resolve) => {
        const timer = setTimeout(resolve, 500);
        video.requestVideoFrameCallback(() => { clearTimeout(timer); resolve(); });
      })
      : Promise.resolve();
    const seeked = new Promise((resolve, reject) => {
      const onSeeked = () => { video.removeEventListener('error', onError); resolve(); };
      const onError = () => { video.removeEventListener('seeked', onSeeked); reject(new Error('/video: seeking failed')); };
      video.addEventListener('seeked', onSeeked, { once: true });
      video.addEventListener('error', onError, { once: true });
    });
    video.currentTime = (n + 0.5) / viewer.info.video.fps;
    return seeked.then(() => presented);
  }

  async function showVideoFrame(n, token) {
    if (!video.paused) video.pause();
    await seekVideo(n);
    if (token !== showing) return;
    uploadVideo();
    showSlider(n);
    await requestDraw();
  }

  // While playing: each new video frame becomes the texture (the headset's frame loop also
  // uploads, since a page's own animation frames may pause in VR).
  function followVideo() {
    if (!playing) return;
    uploadVideo();
    showSlider(videoFrame());
    requestDraw();
    if (video.requestVideoFrameCallback) video.requestVideoFrameCallback(followVideo);
    else requestAnimationFrame(followVideo);
  }

  async function showFrame(n) {
    const token = ++showing;
    const count = viewer.info.frames;
    n = Math.max(0, Math.min(count - 1, Math.trunc(n)));
    if (video) {
      if (playing) stop(false);
      return showVideoFrame(n, token);
    }
    let image;
    try {
      image = await bitmap(n);
    } catch (e) {
      bitmaps.delete(n);
      statusLine.textContent = String(e.message || e);
      throw e;
    }
    if (token !== showing) return;
    gl.bindTexture(gl.TEXTURE_2D, texture);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, image);
    textureHeight = image.height;
    state.frame = n;
    $('frame').value = String(n);
    $('frame-label').textContent = `${n + 1} / ${count}`;
    markStation(n);
    for (let k = 1; k <= 2 && count > 1; k++) bitmap((n + k) % count).catch(() => {});
    await requestDraw();
  }

  // ---- stations: a survey's folder lists where each frame was shot ----

  const SVG = 'http://www.w3.org/2000/svg';

  // The list and the top-down map of the stations /api/info names; picking one shows its
  // frame. The map keeps the plan's proportions: +x right, +y up.
  function setUpStations(stations) {
    const list = $('station-list');
    const map = $('station-map');
    const xs = stations.map((s) => s.position[0]);
    const ys = stations.map((s) => s.position[1]);
    const x0 = Math.min(...xs), y0 = Math.min(...ys);
    const span = Math.max(Math.max(...xs) - x0, Math.max(...ys) - y0) || 1;
    const MARGIN = 10;
    const scale = (100 - 2 * MARGIN) / span;
    // Centre the smaller extent.
    const dx = (100 - 2 * MARGIN - (Math.max(...xs) - x0) * scale) / 2;
    const dy = (100 - 2 * MARGIN - (Math.max(...ys) - y0) * scale) / 2;
    for (const s of stations) {
      const label = s.name || `scan ${s.scan}`;
      const pick = () => showFrame(s.frame).catch(() => {});
      const item = document.createElement('li');
      const button = document.createElement('button');
      button.type = 'button';
      button.textContent = label;
      button.dataset.frame = String(s.frame);
      button.addEventListener('click', pick);
      item.appendChild(button);
      list.appendChild(item);
      const marker = document.createElementNS(SVG, 'circle');
      marker.setAttribute('cx', String(MARGIN + dx + (s.position[0] - x0) * scale));
      marker.setAttribute('cy', String(100 - MARGIN - dy - (s.position[1] - y0) * scale));
      marker.setAttribute('r', '4');
      marker.dataset.frame = String(s.frame);
      const title = document.createElementNS(SVG, 'title');
      title.textContent = label;
      marker.appendChild(title);
      marker.addEventListener('click', pick);
      map.appendChild(marker);
    }
    $('stations').hidden = false;
  }

  // Highlights the station of frame n, if it has one.
  function markStation(n) {
    for (const el of document.querySelectorAll('#station-list button, #station-map circle')) {
      const here = Number(el.dataset.frame) === n;
      if (el.tagName === 'BUTTON') el.setAttribute('aria-current', String(here));
      else el.classList.toggle('current', here);
    }
  }

  // ---- playback ----

  let playing = false;

  // Stops playback; a video settles on the frame the slider shows unless `snap` is false.
  function stop(snap = true) {
    playing = false;
    $('play').textContent = 'Play';
    if (video && !video.paused) {
      video.pause();
      if (snap) showFrame(videoFrame()).catch(() => {});
    }
  }

  async function play() {
    playing = true;
    $('play').textContent = 'Pause';
    if (video) {
      try {
        await video.play();
      } catch (e) {
        stop();
        statusLine.textContent = `/video: ${e.message || e}`;
        throw e;
      }
      followVideo();
      return;
    }
    while (playing) {
      const started = performance.now();
      const fps = Math.max(1, Math.min(60, Number($('fps').value) || 10));
      try {
        await showFrame((state.frame + 1) % viewer.info.frames);
      } catch (e) {
        break;
      }
      const wait = 1000 / fps - (performance.now() - started);
      if (wait > 0) await new Promise((resolve) => setTimeout(resolve, wait));
    }
    playing = false;
    $('play').textContent = 'Play';
  }

  // ---- controls ----

  let drag = null;
  canvas.addEventListener('pointerdown', (e) => {
    drag = { x: e.clientX, y: e.clientY, id: e.pointerId };
    canvas.setPointerCapture(e.pointerId);
    canvas.classList.add('dragging');
  });
  canvas.addEventListener('pointermove', (e) => {
    if (!drag || drag.id !== e.pointerId) return;
    // Grab the image: it follows the pointer, at the angle per pixel of the view's centre.
    const perPixel = 2 * Math.tan(state.fov * RAD / 2) / RAD / canvas.clientHeight;
    state.yaw -= (e.clientX - drag.x) * perPixel;
    state.pitch += (e.clientY - drag.y) * perPixel;
    drag.x = e.clientX;
    drag.y = e.clientY;
    clampView();
    requestDraw();
  });
  const endDrag = () => {
    drag = null;
    canvas.classList.remove('dragging');
  };
  canvas.addEventListener('pointerup', endDrag);
  canvas.addEventListener('pointercancel', endDrag);
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    state.fov *= Math.exp(e.deltaY * 0.001);
    clampView();
    requestDraw();
  }, { passive: false });
  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;
    const step = 5;
    const keys = {
      ArrowLeft: () => { state.yaw -= step; },
      ArrowRight: () => { state.yaw += step; },
      ArrowUp: () => { state.pitch += step; },
      ArrowDown: () => { state.pitch -= step; },
      '+': () => { state.fov /= 1.1; },
      '-': () => { state.fov *= 1.1; },
    };
    if (keys[e.key]) {
      keys[e.key]();
      clampView();
      requestDraw();
    } else if (e.key === ' ' && viewer.info && viewer.info.frames > 1) {
      if (playing) stop(); else play().catch(() => {});
    } else {
      return;
    }
    e.preventDefault();
  });
  window.addEventListener('resize', () => requestDraw());
  $('mode').addEventListener('change', () => viewer.setMode($('mode').value));
  $('frame').addEventListener('input', () => showFrame(Number($('frame').value)).catch(() => {}));
  $('play').addEventListener('click', () => { if (playing) stop(); else play().catch(() => {}); });

  // ---- WebXR ----

  async function setUpXR() {
    const button = $('enter-vr');
    if (!navigator.xr) {
      button.title = 'WebXR is not available here (browsers offer it on https:// or localhost)';
      return;
    }
    let supported = false;
    try {
      supported = await navigator.xr.isSessionSupported('immersive-vr');
    } catch (e) {
      supported = false;
    }
    if (!supported) {
      button.title = 'No VR headset found';
      return;
    }
    button.disabled = false;
    button.title = '';
    button.addEventListener('click', () => {
      if (xr) xr.session.end();
      else enterVR().catch((e) => { statusLine.textContent = `VR: ${e.message || e}`; });
    });
  }

  async function enterVR() {
    const session = await navigator.xr.requestSession('immersive-vr');
    try {
      if (gl.makeXRCompatible) await gl.makeXRCompatible();
      const layer = new XRWebGLLayer(session, gl);
      session.updateRenderState({ baseLayer: layer });
      const space = await session.requestReferenceSpace('local');
      // The headset's forward starts at the heading the page was looking at.
      xr = { session, space, yaw: state.yaw };
    } catch (e) {
      session.end();
      throw e;
    }
    session.addEventListener('end', () => {
      xr = null;
      $('enter-vr').textContent = 'Enter VR';
      requestDraw();
    });
    $('enter-vr').textContent = 'Exit VR';
    session.requestAnimationFrame(drawXR);
  }

  function drawXR(time, frame) {
    if (!xr) return;
    xr.session.requestAnimationFrame(drawXR);
    const pose = frame.getViewerPose(xr.space);
    if (!pose) return;
    if (video && playing) uploadVideo();
    const layer = xr.session.renderState.baseLayer;
    gl.bindFramebuffer(gl.FRAMEBUFFER, layer.framebuffer);
    const heading = rotY(-xr.yaw);
    const views = [];
    for (const view of pose.views) {
      const vp = layer.getViewport(view);
      gl.viewport(vp.x, vp.y, vp.width, vp.height);
      // Each eye samples its own half of an ODS pair; a mono panorama has only one.
      const eye = view.eye === 'right' ? 1 : 0;
      drawView(invert4(view.projectionMatrix), mul3(heading, quatToMat3(view.transform.orientation)), eye);
      views.push({ eye: view.eye, viewport: [vp.x, vp.y, vp.width, vp.height] });
    }
    viewer.xrViews = views;
    viewer.xrFrames += 1;
    // A page that moves the viewer (serve's live walking) reads the controllers here.
    if (viewer.onXRFrame) viewer.onXRFrame(frame, xr.session, pose);
  }

  // ---- the test and scripting surface ----

  // Looks at (yaw, pitch) degrees with a vertical field of view of `fov` degrees; settles
  // once drawn.
  viewer.setView = (yaw, pitch, fov) => {
    state.yaw = Number(yaw);
    state.pitch = Number(pitch);
    if (fov !== undefined) state.fov = Number(fov);
    clampView();
    return requestDraw();
  };
  viewer.view = () => ({ yaw: state.yaw, pitch: state.pitch, fov: state.fov });
  // In VR: the heading (degrees) the headset's forward starts at, and turning it.
  viewer.xrYaw = () => (xr ? xr.yaw : null);
  viewer.turnXR = (deg) => { if (xr) xr.yaw += deg; };
  viewer.setMode = (mode) => {
    if (!(mode in MODES)) throw new Error(`unknown mode ${mode}`);
    state.mode = mode;
    $('mode').value = mode;
    return requestDraw();
  };
  viewer.mode = () => state.mode;
  viewer.setFrame = (n) => showFrame(n);
  viewer.frame = () => state.frame;
  // Starts or stops playback (a tour folder or a video); `play` settles once it runs.
  viewer.play = () => (playing ? Promise.resolve() : play());
  viewer.pause = () => stop();
  viewer.playing = () => playing;
  // For a video: its element's time in seconds and whether it is paused.
  viewer.videoState = () => (video ? { time: video.currentTime, paused: video.paused } : null);

  // Shows `image` (an ImageBitmap decoded without colour-space conversion or premultiplied
  // alpha, at most viewer.maxTexture on a side) as the panorama: `kind` 'mono' (2:1) or
  // 'ods' (1:1, left eye on top). Settles once drawn.
  viewer.maxTexture = maxTexture;
  viewer.showImage = (image, kind) => {
    showing += 1;  // a frame still loading does not replace it
    viewer.info = { kind, width: image.width, height: image.height, frames: 1 };
    gl.bindTexture(gl.TEXTURE_2D, texture);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, image);
    textureHeight = image.height;
    $('mode-box').hidden = kind !== 'ods';
    return requestDraw();
  };

  async function start() {
    // A page that makes its own panoramas (omnicloud serve) hands them over through
    // viewer.showImage; the viewer only sets up its controls and WebXR.
    if (canvas.dataset.source === 'page') {
      statusLine.textContent = '';
      setUpXR();
      return;
    }
    const response = await fetch('/api/info');
    if (!response.ok) throw new Error(`/api/info: ${response.status}`);
    viewer.info = await response.json();
    const { kind, frames } = viewer.info;
    const params = new URLSearchParams(location.search);
    for (const key of ['yaw', 'pitch', 'fov']) {
      if (params.has(key)) state[key] = Number(params.get(key));
    }
    if (kind === 'ods') {
      $('mode-box').hidden = false;
      if (params.has('mode')) state.mode = params.get('mode');
      $('mode').value = state.mode;
    }
    if (frames > 1) {
      $('tour').hidden = false;
      $('frame').max = String(frames - 1);
    }
    if (viewer.info.stations) setUpStations(viewer.info.stations);
    if (viewer.info.video) {
      // A video plays at its own rate.
      $('fps').parentElement.hidden = true;
      await openVideo();
    }
    clampView();
    await showFrame(params.has('frame') ? Number(params.get('frame')) : 0);
    statusLine.textContent = '';
    setUpXR();
  }

  viewer.ready = start().catch((e) => {
    viewer.error = String(e.message || e);
    statusLine.textContent = viewer.error;
    throw e;
  });
})();
