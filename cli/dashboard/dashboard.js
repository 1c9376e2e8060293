// The wall's dashboard (cli/dashboard.h): the tiles to scale with their thumbnails and status,
// the program's rate, plots of the last minutes, and the live effects. Plain JavaScript, no
// library: the page works on a wall's own network, with nothing fetched from outside.
'use strict';

const token = new URLSearchParams(location.search).get('token');
const COLOURS = ['#58a6ff', '#3fb950', '#d29922', '#f778ba', '#a371f7', '#39c5cf', '#ff7b72', '#e3b341'];
const tiles = new Map();  // name -> {div, img, stats, colour}
let wall = null;

function api(path) {
  return token ? path + (path.includes('?') ? '&' : '?') + 'token=' + encodeURIComponent(token) : path;
}

function element(tag, attributes, parent) {
  const e = document.createElement(tag);
  Object.assign(e, attributes || {});
  if (parent) parent.appendChild(e);
  return e;
}

function layOut() {
  const box = document.getElementById('wall');
  const scale = box.clientWidth / wall.width;
  box.style.height = Math.round(wall.height * scale) + 'px';
  for (const t of wall.tiles) {
    const [x, y, w, h] = t.rect;
    Object.assign(tiles.get(t.name).div.style, {
      left: (x * scale) + 'px', top: (y * scale) + 'px', width: (w * scale) + 'px', height: (h * scale) + 'px'});
  }
}

function buildWall() {
  document.getElementById('wall-name').textContent = wall.name || '';
  const box = document.getElementById('wall');
  wall.tiles.forEach((t, i) => {
    const div = element('div', {className: 'tile absent', id: 'tile-' + t.name}, box);
    div.dataset.tile = t.name;
    div.dataset.frame = '';
    const img = element('img', {alt: t.name}, div);
    element('div', {className: 'label', textContent: t.name + (t.machine ? ' @ ' + t.machine : '') + (t.eye ? ' (' + t.eye + ' eye)' : '')}, div);
    const stats = element('div', {className: 'stats', textContent: 'not reported yet'}, div);
    tiles.set(t.name, {div, img, stats, colour: COLOURS[i % COLOURS.length], url: null});
  });
  document.getElementById('units').textContent = {
    pixels: 'Tiles as rectangles of the canvas, ' + wall.width + ' x ' + wall.height + ' pixels.',
    degrees: 'View tiles unrolled: across, the yaw they cover (' + wall.width.toFixed(0) + ' degrees); up, the pitch.',
    window: 'One window, no display config.'}[wall.units] || '';
  layOut();
  window.addEventListener('resize', layOut);
  const legend = document.getElementById('legend');
  element('span', {textContent: 'program'}, legend).style.setProperty('--c', '#ffffff');
  for (const [name, t] of tiles) element('span', {textContent: name}, legend).style.setProperty('--c', t.colour);
}

function buildControls() {
  const box = document.getElementById('effects');
  for (const name of wall.effects) {
    const b = element('button', {id: 'effect-' + name, textContent: name, type: 'button'}, box);
    b.addEventListener('click', () => ask('effects ' + (b.classList.contains('on') ? '-' : '+') + name));
  }
  const select = document.getElementById('param-name');
  for (const p of wall.params) element('option', {value: p.name, textContent: p.name}, select);
  const help = () => {
    const p = wall.params.find(q => q.name === select.value);
    if (!p) return;
    document.getElementById('param-help').textContent = p.help + ' (' + p.min + ' .. ' + p.max + ', default ' + p.value + ')';
    document.getElementById('param-value').placeholder = String(p.value);
  };
  select.addEventListener('change', help);
  help();
  document.getElementById('param-form').addEventListener('submit', e => {
    e.preventDefault();
    ask('param ' + select.value + '=' + document.getElementById('param-value').value.trim());
  });
}

async function ask(request) {
  const reply = document.getElementById('reply');
  try {
    const r = await fetch(api('/api/ctl'), {method: 'POST', body: request, headers: {'X-Glcast-Request': '1'}});
    const j = await r.json();
    reply.textContent = j.reply;
    reply.classList.toggle('error', !j.ok);
  } catch (err) {
    reply.textContent = 'the wall did not answer: ' + err;
    reply.classList.add('error');
  }
  refreshStatus();
}

function plot(canvas, series, unit) {
  // Drawn at the size it is shown, in device pixels: sharp lines and text at any width.
  const ratio = window.devicePixelRatio || 1, W = canvas.clientWidth, H = canvas.clientHeight, left = 40, bottom = 18;
  if (canvas.width !== Math.round(W * ratio) || canvas.height !== Math.round(H * ratio)) {
    canvas.width = Math.round(W * ratio);
    canvas.height = Math.round(H * ratio);
  }
  const g = canvas.getContext('2d');
  g.setTransform(ratio, 0, 0, ratio, 0, 0);
  g.clearRect(0, 0, W, H);
  let top = 1, points = 0;
  for (const s of series) for (const v of s.values) top = Math.max(top, v);
  top = Math.max(4, Math.ceil(top * 1.1));  // whole numbers on the axis
  g.strokeStyle = '#2c333d';
  g.fillStyle = '#8b949e';
  g.font = '11px sans-serif';
  for (let i = 0; i <= 4; i++) {
    const y = (H - bottom) * (1 - i / 4);
    g.beginPath(); g.moveTo(left, y); g.lineTo(W, y); g.stroke();
    g.fillText(String(Math.round(top * i / 4)), 4, Math.max(10, y));
  }
  const n = Math.max(2, ...series.map(s => s.values.length));
  g.fillText('-' + (n - 1) + ' s', left, H - 4);
  g.fillText('now ' + unit, W - 60, H - 4);
  for (const s of series) {
    g.strokeStyle = s.colour;
    g.lineWidth = s.width || 1.5;
    g.beginPath();
    s.values.forEach((v, i) => {
      const x = left + (W - left) * (i + n - s.values.length) / (n - 1), y = (H - bottom) * (1 - v / top);
      if (i === 0) g.moveTo(x, y); else g.lineTo(x, y);
      points++;
    });
    g.stroke();
  }
  canvas.dataset.points = String(points);
}

async function refreshStatus() {
  let j;
  try {
    j = await (await fetch(api('/api/status'))).json();
  } catch (err) {
    document.getElementById('program').textContent = 'the wall is gone (' + err + ')';
    return;
  }
  if (j.latest) {
    const p = j.latest.program;
    document.getElementById('program').textContent =
        'program: frame ' + p.frame + ', ' + p.fps.toFixed(1) + ' fps, ' + p.mbps.toFixed(2) + ' MB/s';
    for (const t of j.latest.tiles) {
      const tile = tiles.get(t.tile);
      if (!tile) continue;
      tile.div.className = 'tile ' + t.state;
      tile.stats.textContent = t.state === 'live' || t.state === 'joining'
          ? t.state + ' f' + t.frame + ' ' + t.fps.toFixed(0) + ' fps lag ' + t.lag + ' rec ' + t.recoveries
          : t.state;
    }
  }
  for (const [name, on] of Object.entries(j.effects.on)) {
    const b = document.getElementById('effect-' + name);
    if (b) b.classList.toggle('on', on);
  }
  const h = j.history;
  const fps = [{colour: '#ffffff', width: 2, values: h.program_fps}];
  const lag = [];
  for (const [name, t] of tiles) {
    const s = h.tiles[name];
    if (!s) continue;
    fps.push({colour: t.colour, values: s.fps});
    lag.push({colour: t.colour, values: s.lag});
  }
  plot(document.getElementById('fps-plot'), fps, 'fps');
  plot(document.getElementById('lag-plot'), lag, 'frames');
}

async function refreshThumbnail(name, tile) {
  try {
    const r = await fetch(api('/api/thumbnail/' + encodeURIComponent(name)));
    if (!r.ok) return;
    const frame = r.headers.get('X-Glcast-Frame');
    const url = URL.createObjectURL(await r.blob());
    tile.img.src = url;
    if (tile.url) URL.revokeObjectURL(tile.url);
    tile.url = url;
    tile.div.dataset.frame = frame;
  } catch (err) {
    // the next look tries again
  }
}

async function start() {
  wall = await (await fetch(api('/api/wall'))).json();
  buildWall();
  buildControls();
  const tick = () => {
    refreshStatus();
    for (const [name, tile] of tiles) refreshThumbnail(name, tile);
  };
  tick();
  setInterval(tick, 1000);
}

start();
