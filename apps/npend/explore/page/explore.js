// npend explore's page: the map as tiles the server computes (GET /api/tile, the values of
// `npend map` for the same options), zoom and pan, and the pendulum of a clicked cell
// (GET /api/trajectory.csv, the CSV of `npend simulate`; GET /api/start, its Lyapunov exponent
// and Poincaré section). The whole view lives in the address's fragment, so an address
// reproduces it. docs/explore.md describes the interface.

const mapCanvas = document.getElementById('map');
const form = document.getElementById('options');
const client = Math.random().toString(36).slice(2);
const SIDE = mapCanvas.width;  // the map canvas is square

// Map options sent to the server as they are (the page's own fields are handled apart).
const MAP_KEYS = ['links', 'masses', 'lengths', 'g', 'com', 'inertia', 'stiffness', 'damping',
  'pivot', 'quantity', 'component', 'phi', 'p', 't-end', 'dt', 'stepper', 'abs-tol', 'rel-tol'];
const CHAIN_KEYS = ['links', 'masses', 'lengths', 'g', 'com', 'inertia', 'stiffness', 'damping',
  'pivot'];
const DEFAULTS = { links: '2', quantity: 'flip', xname: 'phi1', xfrom: '-3.141592653589793',
  xto: '3.141592653589793', yname: 'phi2', yfrom: '-3.141592653589793', yto: '3.141592653589793',
  cells: '64', 't-end': '100', dt: '0.01', stepper: 'rk4' };

let options = {};      // the form's values, by name
let view = null;       // the visible window in axis units: {x0, x1, y0, y1}
let generation = 0;    // bumped at every change of view: the server drops older tiles
const tiles = new Map();  // key -> {values, mask, cells, bounds}
let pending = new Map();  // key -> AbortController
let legend = null;     // the server's X-Npend-Legend
let errorText = '';

// ---- the fragment ----------------------------------------------------------------------

function readFragment() {
  const params = new URLSearchParams(location.hash.slice(1));
  options = { ...DEFAULTS };
  for (const [k, v] of params) if (k !== 'view') options[k] = v;
  const v = params.get('view');
  view = null;
  if (v) {
    const [x0, x1, y0, y1] = v.split(',').map(Number);
    if ([x0, x1, y0, y1].every(Number.isFinite) && x1 > x0 && y1 > y0) view = { x0, x1, y0, y1 };
  }
  if (!view) view = baseWindow();
  for (const el of form.elements) {
    if (!el.name) continue;
    if (el.type === 'checkbox') el.checked = options[el.name] === '1';
    else el.value = options[el.name] ?? '';
  }
}

function writeFragment() {
  const params = new URLSearchParams();
  for (const [k, v] of Object.entries(options)) if (v !== '' && v !== undefined) params.set(k, v);
  params.set('view', [view.x0, view.x1, view.y0, view.y1].join(','));
  history.replaceState(null, '', '#' + params.toString());
}

function readForm() {
  const o = {};
  for (const el of form.elements) {
    if (!el.name) continue;
    if (el.type === 'checkbox') { if (el.checked) o[el.name] = '1'; }
    else if (el.value.trim() !== '') o[el.name] = el.value.trim();
  }
  return o;
}

function baseWindow() {
  return { x0: Number(options.xfrom), x1: Number(options.xto),
    y0: Number(options.yfrom), y1: Number(options.yto) };
}

// ---- tiles -------------------------------------------------------------------------------

// The view at zoom z shows a 2^-z part of the base window; its tiles are those of level
// z + TILE_DEPTH, which split the base window into 2^level x 2^level. Each holds `cells`
// cells a side, sampled at their centres, so that neighbouring tiles continue one grid:
// at zoom 0, 4 x 4 tiles of 64² cells, 256² cells over the canvas's 512² pixels.
const TILE_DEPTH = 2;
function zoomLevel() {
  const base = baseWindow();
  const z = Math.round(Math.log2((base.x1 - base.x0) / (view.x1 - view.x0)));
  return Math.max(0, Math.min(z, 42));  // beyond this doubles no longer tell the cells apart
}

function tileBounds(z, tx, ty) {
  const base = baseWindow();
  const w = (base.x1 - base.x0) / 2 ** z, h = (base.y1 - base.y0) / 2 ** z;
  return { x0: base.x0 + tx * w, x1: base.x0 + (tx + 1) * w,
    y0: base.y0 + ty * h, y1: base.y0 + (ty + 1) * h };
}

function axisText(name, from, to, cells) {
  const step = (to - from) / cells;
  return `${name}:${from + step / 2}:${to - step / 2}:${cells}`;
}

function mapQuery(bounds, cells) {
  const q = new URLSearchParams();
  for (const k of MAP_KEYS) if (options[k] !== undefined && options[k] !== '') q.set(k, options[k]);
  if (options.rods === '1') q.set('rods', '1');
  if (q.get('stepper') === 'rk4') q.delete('stepper');
  q.set('x', axisText(options.xname, bounds.x0, bounds.x1, cells));
  q.set('y', axisText(options.yname, bounds.y0, bounds.y1, cells));
  return q;
}

function visibleTiles() {
  const z = zoomLevel() + TILE_DEPTH, base = baseWindow(), n = 2 ** z;
  const w = (base.x1 - base.x0) / n, h = (base.y1 - base.y0) / n;
  const list = [];
  const tx0 = Math.max(0, Math.floor((view.x0 - base.x0) / w));
  const tx1 = Math.min(n - 1, Math.ceil((view.x1 - base.x0) / w) - 1);
  const ty0 = Math.max(0, Math.floor((view.y0 - base.y0) / h));
  const ty1 = Math.min(n - 1, Math.ceil((view.y1 - base.y0) / h) - 1);
  const cx = (view.x0 + view.x1) / 2, cy = (view.y0 + view.y1) / 2;
  for (let ty = ty0; ty <= ty1; ty++)
    for (let tx = tx0; tx <= tx1; tx++) {
      const b = tileBounds(z, tx, ty);
      list.push({ z, tx, ty, bounds: b,
        distance: Math.hypot((b.x0 + b.x1) / 2 - cx, (b.y0 + b.y1) / 2 - cy) });
    }
  return list.sort((a, b) => a.distance - b.distance);  // the centre first
}

function tileKey(t, cells) { return mapQuery(t.bounds, cells).toString(); }

async function fetchTile(t, cells) {
  const query = mapQuery(t.bounds, cells);
  const key = query.toString();
  if (tiles.has(key) || pending.has(key)) return;
  const abort = new AbortController();
  pending.set(key, abort);
  query.set('client', client);
  query.set('gen', String(generation));
  try {
    const response = await fetch('/api/tile?' + query, { signal: abort.signal });
    if (response.status === 409) return;  // the view moved on
    if (!response.ok) { showError(await response.text()); return; }
    const bytes = await response.arrayBuffer();
    const count = cells * cells;
    const values = new Float64Array(bytes.slice(0, 8 * count));
    const mask = new Uint8Array(bytes.slice(8 * count, 9 * count));
    legend = JSON.parse(response.headers.get('X-Npend-Legend'));
    tiles.set(key, { values, mask, cells, bounds: t.bounds, z: t.z });
    if (tiles.size > 600) tiles.delete(tiles.keys().next().value);
    showError('');
    draw();
  } catch (e) {
    if (e.name !== 'AbortError') showError(String(e));
  } finally {
    pending.delete(key);
    updateStatus();
  }
}

// Coarse tiles first (a quarter of the cells a side), then the full ones.
function requestTiles() {
  const fine = Number(options.cells) || 64, coarse = Math.max(4, Math.round(fine / 4));
  const list = visibleTiles();
  for (const t of list) if (!tiles.has(tileKey(t, fine))) fetchTile(t, coarse);
  for (const t of list) fetchTile(t, fine);
  updateStatus();
}

function viewChanged() {
  generation++;
  for (const abort of pending.values()) abort.abort();
  pending = new Map();
  writeFragment();
  updateDownloads();
  draw();
  requestTiles();
}

// ---- colours -----------------------------------------------------------------------------

// map.png's palette: viridis through five anchors, white for +inf (no flip), red for failed
// cells (NaN), grey where the energy rules a cell out.
const ANCHORS = [[0x44, 0x01, 0x54], [0x3b, 0x52, 0x8b], [0x21, 0x91, 0x8c], [0x5e, 0xc9, 0x62],
  [0xfd, 0xe7, 0x25]];
function viridis(f) {
  const x = Math.min(1, Math.max(0, f)) * 4, i = Math.min(3, Math.floor(x)), r = x - i;
  return ANCHORS[i].map((c, k) => Math.round(c + r * (ANCHORS[i + 1][k] - c)));
}

function colourRange() {
  if (legend && legend.quantity === 'flip') return [legend.dt, legend.t_end];
  let low = Infinity, high = -Infinity;
  for (const t of tiles.values())
    for (const v of t.values) if (Number.isFinite(v)) { low = Math.min(low, v); high = Math.max(high, v); }
  if (legend && legend.logarithmic) low = Math.max(low, 1e-16);
  if (!(high > low)) high = low + 1;
  return [low, high];
}

function colourOf(v, forbidden, range) {
  if (forbidden) return [0xa0, 0xa0, 0xa0];
  if (Number.isNaN(v)) return [0xd6, 0x27, 0x28];
  if (v === Infinity) return [255, 255, 255];
  const log = legend && legend.logarithmic;
  const [low, high] = range;
  const s = (u) => (log ? Math.log(Math.max(u, 1e-16)) : u);
  return viridis((s(v) - s(low)) / (s(high) - s(low)));
}

// ---- drawing ----------------------------------------------------------------------------

function toCanvas(x, y) {
  return [(x - view.x0) / (view.x1 - view.x0) * SIDE, (view.y1 - y) / (view.y1 - view.y0) * SIDE];
}

function tileImage(t, range) {
  const c = document.createElement('canvas');
  c.width = t.cells; c.height = t.cells;
  const ctx = c.getContext('2d'), image = ctx.createImageData(t.cells, t.cells);
  for (let j = 0; j < t.cells; j++)
    for (let i = 0; i < t.cells; i++) {
      const k = j * t.cells + i, p = ((t.cells - 1 - j) * t.cells + i) * 4;  // row 0 at the bottom
      const [r, g, b] = colourOf(t.values[k], t.mask[k], range);
      image.data[p] = r; image.data[p + 1] = g; image.data[p + 2] = b; image.data[p + 3] = 255;
    }
  ctx.putImageData(image, 0, 0);
  return c;
}

function draw() {
  const ctx = mapCanvas.getContext('2d');
  ctx.imageSmoothingEnabled = false;
  ctx.fillStyle = '#d0d0d0';
  ctx.fillRect(0, 0, SIDE, SIDE);
  const range = colourRange();
  const fine = Number(options.cells) || 64, coarse = Math.max(4, Math.round(fine / 4));
  for (const t of visibleTiles()) {
    const tile = tiles.get(tileKey(t, fine)) || tiles.get(tileKey(t, coarse));
    if (!tile) continue;
    const [ax, ay] = toCanvas(t.bounds.x0, t.bounds.y1), [bx, by] = toCanvas(t.bounds.x1, t.bounds.y0);
    ctx.drawImage(tileImage(tile, range), ax, ay, bx - ax, by - ay);
  }
  drawMarker(ctx);
  drawColourbar(range);
  document.getElementById('legend').textContent = legend ? legend.title : '';
  document.getElementById('view').textContent =
    `${options.xname} ${view.x0.toPrecision(8)} … ${view.x1.toPrecision(8)}, ` +
    `${options.yname} ${view.y0.toPrecision(8)} … ${view.y1.toPrecision(8)} (zoom 2^${zoomLevel()})`;
}

function drawColourbar(range) {
  const c = document.getElementById('colorbar'), ctx = c.getContext('2d');
  ctx.clearRect(0, 0, c.width, c.height);
  for (let x = 0; x < c.width; x++) {
    const [r, g, b] = viridis(x / (c.width - 1));
    ctx.fillStyle = `rgb(${r},${g},${b})`;
    ctx.fillRect(x, 0, 1, 18);
  }
  ctx.fillStyle = '#222';
  ctx.font = '12px sans-serif';
  ctx.fillText(range[0].toPrecision(3), 0, 32);
  const hi = range[1].toPrecision(3);
  ctx.fillText(hi, c.width - ctx.measureText(hi).width, 32);
  const label = legend ? `${legend.label}${legend.logarithmic ? ' (log scale)' : ''}` : '';
  ctx.fillText(label, (c.width - ctx.measureText(label).width) / 2, 32);
}

function updateStatus() {
  const fine = Number(options.cells) || 64;
  const list = visibleTiles();
  const done = list.filter((t) => tiles.has(tileKey(t, fine))).length;
  document.getElementById('status').textContent = done === list.length
    ? `${done} tiles of ${fine}² cells: done`
    : `${done} of ${list.length} tiles of ${fine}² cells; computing…`;
}

function showError(text) {
  errorText = text;
  document.getElementById('error').textContent = text;
}

// ---- zoom, pan, click ------------------------------------------------------------------

function axisAt(px, py) {
  return [view.x0 + px / SIDE * (view.x1 - view.x0), view.y1 - py / SIDE * (view.y1 - view.y0)];
}

function zoomAt(px, py, factor) {
  const [x, y] = axisAt(px, py);
  view = { x0: x + (view.x0 - x) * factor, x1: x + (view.x1 - x) * factor,
    y0: y + (view.y0 - y) * factor, y1: y + (view.y1 - y) * factor };
  viewChanged();
}

mapCanvas.addEventListener('wheel', (e) => {
  e.preventDefault();
  zoomAt(e.offsetX, e.offsetY, e.deltaY < 0 ? 0.5 : 2);
}, { passive: false });

let drag = null;
mapCanvas.addEventListener('mousedown', (e) => { drag = { x: e.offsetX, y: e.offsetY, moved: false, start: { ...view } }; });
mapCanvas.addEventListener('mousemove', (e) => {
  if (!drag) return;
  const dx = e.offsetX - drag.x, dy = e.offsetY - drag.y;
  if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
  if (!drag.moved) return;
  const w = drag.start.x1 - drag.start.x0, h = drag.start.y1 - drag.start.y0;
  view = { x0: drag.start.x0 - dx / SIDE * w, x1: drag.start.x1 - dx / SIDE * w,
    y0: drag.start.y0 + dy / SIDE * h, y1: drag.start.y1 + dy / SIDE * h };
  draw();
});
window.addEventListener('mouseup', (e) => {
  if (!drag) return;
  const d = drag;
  drag = null;
  if (d.moved) viewChanged();
  else if (e.target === mapCanvas) selectCell(e.offsetX, e.offsetY);
});

form.addEventListener('submit', (e) => {
  e.preventDefault();
  options = readForm();
  view = baseWindow();  // new options: the whole window again
  tiles.clear();
  legend = null;
  viewChanged();
});

// ---- the pendulum of a cell -----------------------------------------------------------

let trajectory = null;  // {columns: {name: Float64Array}, rows, flip, query}
let frame = 0, playing = false, selected = null;

// The cell under the pointer: its value and its start, the base start with the axes' values.
function cellAt(px, py) {
  const fine = Number(options.cells) || 64;
  const [x, y] = axisAt(px, py);
  for (const t of visibleTiles()) {
    const b = t.bounds;
    if (x < b.x0 || x >= b.x1 || y < b.y0 || y >= b.y1) continue;
    const tile = tiles.get(tileKey(t, fine));
    const i = Math.min(fine - 1, Math.floor((x - b.x0) / (b.x1 - b.x0) * fine));
    const j = Math.min(fine - 1, Math.floor((y - b.y0) / (b.y1 - b.y0) * fine));
    // The cell's coordinates as the server computes them (grid_value, the same operations
    // in the same order): the start of the clicked cell is the start of its map value.
    const q = mapQuery(b, fine);
    const [, x0, x1] = q.get('x').split(':').map(Number), [, y0, y1] = q.get('y').split(':').map(Number);
    return { x: x0 + (x1 - x0) * i / (fine - 1), y: y0 + (y1 - y0) * j / (fine - 1),
      value: tile ? tile.values[j * fine + i] : undefined };
  }
  return null;
}

function startOf(cell) {
  const n = Number(options.links);
  const list = (text) => {
    const parts = (text || '').split(',').map((s) => s.trim()).filter((s) => s !== '');
    return parts.length === n ? parts.map(Number) : (parts.length === 1 ? Array(n).fill(Number(parts[0])) : Array(n).fill(0));
  };
  const phi = list(options.phi), p = list(options.p);
  for (const [name, v] of [[options.xname, cell.x], [options.yname, cell.y]]) {
    const m = /^(phi|p)(\d+)$/.exec(name);
    if (!m || Number(m[2]) < 1 || Number(m[2]) > n) return null;
    (m[1] === 'phi' ? phi : p)[Number(m[2]) - 1] = v;
  }
  return { phi, p };
}

function startQuery(start, tEnd) {
  const q = new URLSearchParams();
  for (const k of CHAIN_KEYS) if (options[k]) q.set(k, options[k]);
  if (options.rods === '1') q.set('rods', '1');
  q.set('phi', start.phi.join(','));
  q.set('p', start.p.join(','));
  q.set('t-end', String(tEnd));
  // The map's stepper and step, so that the pendulum flips when its cell says it does.
  q.set('stepper', options.stepper || 'rk4');
  q.set('dt', options.dt || '0.01');
  for (const k of ['abs-tol', 'rel-tol']) if (options[k]) q.set(k, options[k]);
  return q;
}

async function selectCell(px, py) {
  const cell = cellAt(px, py);
  if (!cell) return;
  const start = startOf(cell);
  if (!start) {
    showError('A click starts a pendulum where both axes are start angles or momenta (phiK, pK).');
    return;
  }
  selected = cell;
  draw();
  const tEnd = Math.min(Number(options['t-end']) || 20, 60);
  const q = startQuery(start, tEnd);
  const dt = Number(options.dt) || 0.01;
  const every = Math.max(1, Math.ceil(tEnd / dt / 20000));
  const tq = new URLSearchParams(q);
  if (every > 1) tq.set('every', String(every));
  document.getElementById('start-title').textContent =
    `φ = (${start.phi.map((v) => v.toPrecision(6)).join(', ')}), ` +
    `p = (${start.p.map((v) => v.toPrecision(6)).join(', ')})` +
    (cell.value !== undefined ? `; map value ${cell.value}` : '');
  document.getElementById('download-csv').href = '/api/trajectory.csv?' + tq;
  const response = await fetch('/api/trajectory.csv?' + tq);
  if (!response.ok) { showError(await response.text()); return; }
  trajectory = parseCsv(await response.text());
  trajectory.flip = legend && legend.quantity === 'flip' && Number.isFinite(cell.value) ? cell.value : null;
  trajectory.query = tq.toString();
  frame = 0;
  const scrub = document.getElementById('scrub');
  scrub.max = String(trajectory.rows - 1);
  scrub.value = '0';
  plotSeries();
  drawPendulum();
  fetchAnalysis(q);
}

function parseCsv(text) {
  const lines = text.trim().split('\n');
  const names = lines[0].split(',');
  const columns = {};
  for (const name of names) columns[name] = new Float64Array(lines.length - 1);
  for (let r = 1; r < lines.length; r++) {
    const cells = lines[r].split(',');
    for (let c = 0; c < names.length; c++) columns[names[c]][r - 1] = Number(cells[c]);
  }
  return { columns, names, rows: lines.length - 1 };
}

async function fetchAnalysis(q) {
  const out = document.getElementById('lyapunov');
  out.textContent = 'Lyapunov exponent: computing…';
  const response = await fetch('/api/start?' + q);
  if (!response.ok) { out.textContent = await response.text(); return; }
  const a = await response.json();
  out.textContent = a.lyapunov !== undefined
    ? `maximal Lyapunov exponent over ${q.get('t-end')} s: ${a.lyapunov.toPrecision(4)} 1/s ` +
      `(± ${a.lyapunov_standard_error.toPrecision(2)})`
    : `Lyapunov exponent: ${a.lyapunov_problem}`;
  const box = document.getElementById('section');
  if (a.section && a.section.points.length > 0) {
    const points = a.section.points.slice().sort((u, v) => u[0] - v[0]);
    new Dygraph(box, points, { labels: [a.section.x, a.section.y], drawPoints: true,
      strokeWidth: 0, pointSize: 1.5, title: `Poincaré section ${a.section.plane}`,
      xlabel: 'φ₂ (rad)', ylabel: 'p₂' });
  } else {
    box.textContent = a.section_problem || 'no crossings of the section';
  }
}

function plotSeries() {
  const c = trajectory.columns, n = Number(options.links);
  const angles = [], energy = [];
  const h0 = c.H[0];
  for (let r = 0; r < trajectory.rows; r++) {
    const row = [c.t[r]];
    for (let i = 1; i <= n; i++) row.push(c[`phi_${i}`][r]);
    angles.push(row);
    energy.push([c.t[r], (c.H[r] - h0) / Math.abs(h0)]);
  }
  const flip = trajectory.flip;
  const mark = (canvas, area, g) => {
    if (flip === null) return;
    const x = g.toDomXCoord(flip);
    canvas.fillStyle = 'rgba(214,39,40,0.8)';
    canvas.fillRect(x - 1, area.y, 2, area.h);
  };
  const labels = ['t'];
  for (let i = 1; i <= n; i++) labels.push(`φ${i}`);
  new Dygraph(document.getElementById('angles'), angles, { labels, title:
    flip === null ? 'angles (rad)' : `angles (rad); red: the flip at t = ${flip.toPrecision(6)} s`,
    underlayCallback: mark });
  new Dygraph(document.getElementById('energy'), energy, { labels: ['t', '(H − H₀)/|H₀|'],
    title: 'relative energy error', underlayCallback: mark });
}

// The pendulum's drawing: the pivot at the canvas's centre, `scale` pixels per metre, y down
// (the CSV's y is the depth below the pivot).
function pendulumTransform() {
  const c = trajectory.columns, n = Number(options.links);
  let reach = 0;
  for (let i = 1; i <= n; i++) reach = Math.max(reach, Math.hypot(c[`x_${i}`][0], c[`y_${i}`][0]));
  let total = 0;
  for (const l of (options.lengths || '').split(',')) total += Number(l) || 0;
  if (!(total > 0)) total = n * (Number(options.lengths) || 1);
  const canvas = document.getElementById('pendulum');
  return { cx: canvas.width / 2, cy: canvas.height / 2,
    scale: (canvas.width / 2 - 12) / Math.max(total, reach, 1e-9) };
}

function bobOnCanvas(i, row) {
  const c = trajectory.columns, tr = pendulumTransform();
  return [tr.cx + tr.scale * c[`x_${i}`][row], tr.cy + tr.scale * c[`y_${i}`][row]];
}

function drawPendulum() {
  if (!trajectory) return;
  const canvas = document.getElementById('pendulum'), ctx = canvas.getContext('2d');
  const c = trajectory.columns, n = Number(options.links), tr = pendulumTransform();
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const t = c.t[frame];
  // The trail of the last bob over the last 2 s.
  ctx.strokeStyle = 'rgba(59,82,139,0.35)';
  ctx.beginPath();
  for (let r = frame; r >= 0 && c.t[frame] - c.t[r] <= 2; r--) {
    const [x, y] = bobOnCanvas(n, r);
    if (r === frame) ctx.moveTo(x, y); else ctx.lineTo(x, y);
  }
  ctx.stroke();
  ctx.strokeStyle = '#222';
  ctx.lineWidth = 2;
  ctx.beginPath();
  ctx.moveTo(tr.cx, tr.cy);
  for (let i = 1; i <= n; i++) ctx.lineTo(...bobOnCanvas(i, frame));
  ctx.stroke();
  const flipped = trajectory.flip !== null && t >= trajectory.flip;
  for (let i = 1; i <= n; i++) {
    const [x, y] = bobOnCanvas(i, frame);
    ctx.fillStyle = flipped ? '#d62728' : '#21918c';
    ctx.beginPath();
    ctx.arc(x, y, 6, 0, 2 * Math.PI);
    ctx.fill();
  }
  ctx.fillStyle = '#222';
  ctx.fillRect(tr.cx - 3, tr.cy - 3, 6, 6);
  document.getElementById('clock').textContent = `t = ${t.toFixed(2)} s` +
    (trajectory.flip !== null ? (flipped ? ' (flipped)' : `; flips at ${trajectory.flip.toFixed(3)} s`) : '');
  document.getElementById('scrub').value = String(frame);
}

function setFrame(r) {
  frame = Math.max(0, Math.min(trajectory.rows - 1, r));
  drawPendulum();
}

document.getElementById('scrub').addEventListener('input', (e) => {
  if (trajectory) setFrame(Number(e.target.value));
});
document.getElementById('play').addEventListener('click', (e) => {
  if (!trajectory) return;
  playing = !playing;
  e.target.textContent = playing ? 'pause' : 'play';
  if (playing) requestAnimationFrame(animate(performance.now(), trajectory.columns.t[frame]));
});

function animate(wallStart, tStart) {
  return function step(now) {
    if (!playing || !trajectory) return;
    const speed = Number(document.getElementById('speed').value);
    const t = tStart + (now - wallStart) / 1000 * speed, c = trajectory.columns.t;
    let r = frame;
    while (r + 1 < trajectory.rows && c[r + 1] <= t) r++;
    setFrame(r);
    if (r + 1 < trajectory.rows) requestAnimationFrame(step);
    else { playing = false; document.getElementById('play').textContent = 'play'; }
  };
}

function drawMarker(ctx) {
  if (!selected) return;
  const [x, y] = toCanvas(selected.x, selected.y);
  ctx.strokeStyle = '#d62728';
  ctx.lineWidth = 2;
  ctx.strokeRect(x - 5, y - 5, 10, 10);
}

// ---- downloads -------------------------------------------------------------------------

function updateDownloads() {
  const q = mapQuery(view, 256);
  document.getElementById('download-npy').href = '/api/map.npy?' + q;
  const args = ['npend map'];
  for (const [k, v] of q) args.push(k === 'rods' ? '--rods' : `--${k} ${/^[\w.,:+\-/=]+$/.test(v) ? v : `'${v}'`}`);
  args.push('--out map');
  document.getElementById('command').textContent = args.join(' ');
}

document.getElementById('download-png').addEventListener('click', (e) => {
  e.preventDefault();
  const a = document.createElement('a');
  a.href = mapCanvas.toDataURL('image/png');
  a.download = 'map.png';
  a.click();
});

// ---- start -------------------------------------------------------------------------------

window.addEventListener('hashchange', () => { readFragment(); tiles.clear(); viewChanged(); });
readFragment();
viewChanged();

// What the tests read (tests/explore/).
window.npendExplore = {
  get view() { return { ...view }; },
  get options() { return { ...options }; },
  get error() { return errorText; },
  get trajectory() { return trajectory; },
  tiles, tileKey, visibleTiles, toCanvas, zoomAt, selectCell, setFrame, bobOnCanvas,
  pendulumTransform,
  done() {
    const fine = Number(options.cells) || 64;
    return visibleTiles().every((t) => tiles.has(tileKey(t, fine)));
  },
};
