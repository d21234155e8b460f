// omnicloud serve: a map of the scan to stand on and sliders for the stereo settings; each
// change asks the server for a new ODS pair (/api/render) and hands it to the viewer
// (viewer.js) through viewer.showImage. Requests carry the page's name and a sequence
// number: the server renders only the newest of a page's waiting requests and answers the
// others 409, and an answer older than the one on screen is dropped, so a fast slider always
// ends on its last value. A newest request answered 503 (too many renders waiting) is asked
// again after the Retry-After pause.
'use strict';

(() => {
  const $ = (id) => document.getElementById(id);
  const statusLine = $('status');
  const viewer = window.viewer;

  const live = {
    // This page's name in the server's render queue: its requests replace only each other.
    client: Math.random().toString(36).slice(2, 12),
    scan: null,         // /api/scan
    camera: null,       // [x, y] file coordinates asked for
    seq: 0,             // the newest request's number
    shownSeq: 0,        // the number of the render on screen
    lastRender: null,   // { seq, url, camera: [x, y, z], ms }
    error: null,
  };
  window.live = live;

  // Pole merge sliders: start and end angles from the pole (end <= start), exponent.
  const POLES = ['north', 'south'];
  const PARTS = ['start', 'end', 'exponent'];

  function parseMerge(text) {
    const m = /^marrinan:([^,]+),([^,]+),([^,]+)$/.exec(text);
    return m ? { start: Number(m[1]), end: Number(m[2]), exponent: Number(m[3]) }
      : { start: 0, end: 0, exponent: 1 };
  }

  function mergeOf(pole) {
    const v = (part) => Number($(`${pole}-${part}`).value);
    return `marrinan:${v('start')},${v('end')},${v('exponent')}`;
  }

  function showValues() {
    $('ipd-value').textContent = Number($('ipd').value).toFixed(3);
    for (const pole of POLES) {
      for (const part of PARTS) {
        $(`${pole}-${part}-value`).textContent = $(`${pole}-${part}`).value;
      }
      // Start 0 turns merging off: the other two have no effect then.
      const off = Number($(`${pole}-start`).value) === 0;
      $(`${pole}-end`).disabled = off;
      $(`${pole}-exponent`).disabled = off;
    }
  }

  // ---- the map: pixel <-> file coordinates by the grid /api/scan describes ----

  // File XY at a point of the map image, in CSS pixels from its top left corner.
  function fileAt(offsetX, offsetY) {
    const grid = live.scan.map;
    const box = $('map').getBoundingClientRect();
    const mx = offsetX / box.width * grid.width;
    const my = offsetY / box.height * grid.height;
    return [grid.x0 + mx * grid.pixel, grid.y1 - my * grid.pixel];
  }

  function placeMarker(x, y) {
    const grid = live.scan.map;
    const marker = $('marker');
    marker.style.left = `${(x - grid.x0) / grid.pixel / grid.width * 100}%`;
    marker.style.top = `${(grid.y1 - y) / grid.pixel / grid.height * 100}%`;
    marker.hidden = false;
  }

  // ---- renders ----

  const waiting = [];  // { seq, resolve } until a render at least that new is shown

  function settle() {
    for (let i = waiting.length - 1; i >= 0; i--) {
      if (waiting[i].seq <= live.shownSeq) waiting.splice(i, 1)[0].resolve(live.lastRender);
    }
  }

  // Busy answers in a row asked again for before the page shows the error.
  const MAX_RETRIES = 5;
  let retries = 0;

  async function request() {
    if (!live.camera) return;  // a slider moved before the scan's description arrived
    const seq = ++live.seq;
    const [x, y] = live.camera;
    const query = new URLSearchParams({
      x: String(x), y: String(y), ipd: $('ipd').value,
      north: mergeOf('north'), south: mergeOf('south'), seq: String(seq), client: live.client,
    });
    const url = `/api/render?${query}`;
    $('timing').textContent = 'rendering…';
    let response;
    try {
      response = await fetch(url);
    } catch (e) {
      statusLine.textContent = `render: ${e.message || e}`;
      return;
    }
    // Every body is read to its end: an unread one holds its connection, and the browser's
    // few connections per server would soon all wait.
    const body = await response.blob();
    // A newer request replaced this one on the server, or one already shows a newer frame.
    if (response.status === 409 || seq < live.shownSeq) return;
    // The server had as many renders waiting as it lets wait (a burst over this page's
    // connections, or other pages rendering): ask again for the newest settings, after the
    // pause it names.
    const retryAfter = Number(response.headers.get('Retry-After'));
    if (response.status === 503 && retryAfter > 0 && seq === live.seq && retries < MAX_RETRIES) {
      retries += 1;
      $('timing').textContent = 'server busy, asking again…';
      setTimeout(request, Math.min(retryAfter, 5) * 1000);
      return;
    }
    if (!response.ok) {
      retries = 0;
      live.error = `render: ${response.status} ${(await body.text()).trim()}`;
      statusLine.textContent = live.error;
      live.shownSeq = Math.max(live.shownSeq, seq);
      settle();
      return;
    }
    const camera = (response.headers.get('X-Omnicloud-Camera') || '').split(',').map(Number);
    const ms = Number(response.headers.get('X-Omnicloud-Render-Ms'));
    const size = Math.min(1, viewer.maxTexture / live.scan.width);
    const options = { colorSpaceConversion: 'none', premultiplyAlpha: 'none', imageOrientation: 'none' };
    if (size < 1) {
      options.resizeWidth = Math.floor(live.scan.width * size);
      options.resizeHeight = options.resizeWidth;
      options.resizeQuality = 'high';
    }
    const image = await createImageBitmap(body, options);
    if (seq < live.shownSeq) return;
    live.shownSeq = seq;
    retries = 0;
    live.error = null;
    statusLine.textContent = '';
    live.lastRender = { seq, url, camera, ms };
    $('camera').textContent =
      `camera ${camera[0].toFixed(2)}, ${camera[1].toFixed(2)}, ${camera[2].toFixed(2)}`;
    placeMarker(camera[0], camera[1]);
    await viewer.showImage(image, 'ods');
    $('timing').textContent = seq === live.seq ? `rendered in ${ms.toFixed(0)} ms` : 'rendering…';
    settle();
  }

  // Settles with live.lastRender once the newest request so far (or a newer one) is shown.
  live.settled = () => new Promise((resolve) => {
    waiting.push({ seq: live.seq, resolve });
    settle();
  });

  // Stands the camera at file (x, y) and renders; settles once shown.
  live.standAt = (x, y) => {
    live.camera = [Number(x), Number(y)];
    request();
    return live.settled();
  };

  function changed() {
    showValues();
    request();
  }

  // ---- controls ----

  $('map').addEventListener('click', (e) => {
    const box = $('map').getBoundingClientRect();
    live.camera = fileAt(e.clientX - box.left, e.clientY - box.top);
    request();
  });
  $('ipd').addEventListener('input', changed);
  for (const pole of POLES) {
    $(`${pole}-start`).addEventListener('input', () => {
      const start = Number($(`${pole}-start`).value);
      if (Number($(`${pole}-end`).value) > start) $(`${pole}-end`).value = String(start);
      changed();
    });
    $(`${pole}-end`).addEventListener('input', () => {
      const start = Number($(`${pole}-start`).value);
      if (Number($(`${pole}-end`).value) > start) $(`${pole}-end`).value = String(start);
      changed();
    });
    $(`${pole}-exponent`).addEventListener('input', changed);
  }
  $('toggle-panel').addEventListener('click', () => {
    const panel = $('panel');
    panel.hidden = !panel.hidden;
    $('toggle-panel').textContent = panel.hidden ? 'Show map' : 'Hide map';
  });

  async function start() {
    await viewer.ready;
    const response = await fetch('/api/scan');
    if (!response.ok) throw new Error(`/api/scan: ${response.status}`);
    live.scan = await response.json();
    document.title = `omnicloud serve: ${live.scan.file}`;
    $('ipd').value = String(live.scan.ipd);
    const merge = parseMerge(live.scan.pole_merge);
    for (const pole of POLES) {
      for (const part of PARTS) $(`${pole}-${part}`).value = String(merge[part]);
    }
    showValues();
    const [x, y] = live.scan.camera;
    await live.standAt(x, y);
  }

  live.ready = start().catch((e) => {
    live.error = String(e.message || e);
    statusLine.textContent = live.error;
    throw e;
  });
})();
