#!/usr/bin/env node
// A stand-in for lpss-view's HTTP side, to test the page without the C++ server: it serves the
// same URLs (the page, Debian's three.js, /events) and a made-up world on /events in the protocol
// lpss-view speaks:
//   event: world   {"sector_size", "hysteresis", "region", "workers"}
//   event: kinds   {"bodies": [{"id", "name", "shape", ...shape fields, "mass"}]}  (before any frame using them)
//   event: frame   {"frame", "every_body", "bodies": [[id,x,y,z,qx,qy,qz,qw,worker,awake,cloned]],
//                   "departed", "handoffs": [[body,from,to,frame]], "workers": [{id,sectors,bodies,ghosts,clones,awake}],
//                   "time_lost", "started_ms"}
// The world: one body of every shape around the border x = 64 between sector 0 (worker 1) and
// sector 1 (worker 2), some asleep, a "runner" that crosses that border (handoffs, clones), a body
// that comes and goes (kinds mid-stream, departed), and three bodies 1e12 units out on x.
// The simulation runs at 60 frames/s and events go out at 30/s, so every event skips frames, and
// now and then a longer gap, as lpss-view does.
//
//   node tests/view/fake_stream.js [--port P (0: any; the URL is printed)] [--rate HZ] [--empty] [--region]
//                                  [--page DIR] [--three DIR]
'use strict';

const http = require('http');
const fs = require('fs');
const path = require('path');

function parseArgs(argv) {
  const o = { port: 0, rate: 30, empty: false, region: false,
    page: path.resolve(__dirname, '../../client/view/page'), three: '/usr/share/javascript/three' };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    const next = () => {
      if (i + 1 >= argv.length) { console.error(`fake_stream: ${a} needs a value`); process.exit(2); }
      return argv[++i];
    };
    if (a === '--port') o.port = Number(next());
    else if (a === '--rate') o.rate = Number(next());
    else if (a === '--page') o.page = path.resolve(next());
    else if (a === '--three') o.three = path.resolve(next());
    else if (a === '--empty') o.empty = true;
    else if (a === '--region') o.region = true;
    else if (a === '--help' || a === '-h') {
      console.log('node tests/view/fake_stream.js [--port P] [--rate HZ] [--empty] [--region] [--page DIR] [--three DIR]');
      process.exit(0);
    } else { console.error(`fake_stream: unknown argument ${a}`); process.exit(2); }
  }
  if (!Number.isInteger(o.port) || o.port < 0 || o.port > 65535) { console.error('fake_stream: bad --port'); process.exit(2); }
  if (!(o.rate > 0 && o.rate <= 60)) { console.error('fake_stream: --rate must be in (0, 60]'); process.exit(2); }
  return o;
}
const opts = parseArgs(process.argv.slice(2));

// The same paths lpss-view serves.
const FILES = {
  '/': [opts.page, 'index.html'],
  '/index.html': [opts.page, 'index.html'],
  '/viewer.js': [opts.page, 'viewer.js'],
  '/viewer.css': [opts.page, 'viewer.css'],
  '/three/three.min.js': [opts.three, 'three.min.js'],
  '/three/OrbitControls.js': [opts.three, 'examples/js/controls/OrbitControls.js'],
  '/three/ConvexHull.js': [opts.three, 'examples/js/math/ConvexHull.js'],
  '/three/ConvexGeometry.js': [opts.three, 'examples/js/geometries/ConvexGeometry.js'],
};
const TYPES = { '.html': 'text/html; charset=utf-8', '.js': 'text/javascript; charset=utf-8', '.css': 'text/css; charset=utf-8' };

// ---------------------------------------------------------------------------------------------
// The world.
const L = 128;
const SIM_HZ = 60;
// 1e12 + 3/8: a double holds it exactly (its spacing there is 2^-13), so a test can compare exactly.
const FAR_X = 1000000000000.375;
const KINDS = [
  { id: 1, name: 'ground', shape: 'plane', normal: [0, 1, 0], offset: -1, mass: 0 },
  { id: 2, name: 'ball', shape: 'sphere', radius: 0.5, mass: 1 },
  { id: 3, name: 'crate', shape: 'box', half: [0.6, 0.4, 0.5], mass: 2 },
  { id: 4, name: 'pill', shape: 'capsule', radius: 0.3, height: 1.0, mass: 1 },
  { id: 5, name: 'rock', shape: 'hull', mass: 3,
    points: [[0.7, 0, 0], [-0.6, 0.1, 0.2], [0, 0.6, 0], [0.1, -0.5, 0.1], [0, 0.1, 0.7], [0.2, 0, -0.6], [0.4, 0.4, 0.3]] },
  { id: 6, name: 'sleeper', shape: 'sphere', radius: 0.4, mass: 1 },
  { id: 7, name: 'crate-asleep', shape: 'box', half: [0.5, 0.5, 0.5], mass: 1 },
  { id: 8, name: 'runner', shape: 'sphere', radius: 0.5, mass: 1 },
  { id: 9, name: 'tower', shape: 'box', half: [0.5, 2, 0.5], mass: 0 },
  { id: 10, name: 'blink', shape: 'capsule', radius: 0.25, height: 0.6, mass: 1 },
  { id: 100, name: 'far', shape: 'sphere', radius: 0.5, mass: 1 },
  { id: 101, name: 'far-crate', shape: 'box', half: [0.3, 0.3, 0.3], mass: 1 },
  { id: 102, name: 'far-rock', shape: 'hull', mass: 1,
    points: [[0.5, 0, 0], [-0.5, 0, 0], [0, 0.8, 0], [0, 0, 0.5], [0, 0, -0.5], [0, -0.3, 0]] },
];
const kindById = new Map(KINDS.map((k) => [k.id, k]));

const axisAngle = (ax, ay, az, a) => [ax * Math.sin(a / 2), ay * Math.sin(a / 2), az * Math.sin(a / 2), Math.cos(a / 2)];
const ID = [0, 0, 0, 1];
const sectorOf = (x) => Math.round(x / L);
// Sectors i <= 0 belong to worker 1, the others to worker 2.
const ownerAt = (p) => (sectorOf(p[0]) <= 0 ? 1 : 2);
// Within 4 units of a sector border on any axis: a neighbour holds a clone.
const nearBorder = (p) => p.some((x) => Math.abs(x / L - Math.round(x / L)) > 0.5 - 4 / L);

let runnerOwner = 1;   // with hysteresis: it changes hands 1.5 units past the border
function bodiesAt(frame) {
  if (opts.empty) return [];
  const t = frame / SIM_HZ;
  const list = [];
  const add = (id, p, q, awake, owner) => {
    list.push([id, p[0], p[1], p[2], q[0], q[1], q[2], q[3], owner === undefined ? ownerAt(p) : owner,
      awake ? 1 : 0, nearBorder(p) ? 1 : 0]);
  };
  add(1, [0, 0, 0], ID, 0, 1);
  add(2, [60 + 2.5 * Math.cos(t), -0.5, 2.5 * Math.sin(t)], axisAngle(0, 0, 1, -t * 5), 1);
  add(3, [61, -0.6, -3], axisAngle(0, 1, 0, t * 0.8), 1);
  add(4, [67, 0, 2.5], axisAngle(0, 0, 1, t * 1.3), 1);
  add(5, [58, -0.4, 3], axisAngle(0.6, 0.8, 0, 0.7), 0);
  add(6, [68, -0.6, -2.5], ID, 0);
  add(7, [70, -0.5, 1], axisAngle(0, 1, 0, 0.4), 0);
  const rx = 64 + 6 * Math.sin(0.7 * t);
  if (runnerOwner === 1 && rx > 64 + 1.5) runnerOwner = 2;
  if (runnerOwner === 2 && rx < 64 - 1.5) runnerOwner = 1;
  add(8, [rx, -0.5, 0.8], axisAngle(0, 0, 1, -(rx - 64) * 2), 1, runnerOwner);
  add(9, [72, 1, -4], ID, 0);
  if (t % 5 < 3) add(10, [64, 2.5 + 0.3 * Math.sin(3 * t), -1], axisAngle(1, 0, 0, t), 1);
  add(100, [FAR_X, 2.5, -3.25], ID, 0);
  add(101, [FAR_X + 2 * Math.cos(t), 2.5, -3.25 + 2 * Math.sin(t)], axisAngle(0, 1, 0, t * 2), 1);
  add(102, [FAR_X - 3, 2.5, -3.25], axisAngle(0, 0, 1, 0.3), 1);
  return list;
}

let frame = 0;
let rows = bodiesAt(0);
let timeLost = 0;
const handoffLog = [];          // [body, from, to, frame], newest last
const startedMs = Date.now();
let lastOwner = new Map(rows.map((r) => [r[0], r[8]]));

function step() {
  frame += 1;
  rows = bodiesAt(frame);
  for (const r of rows) {
    const before = lastOwner.get(r[0]);
    if (before !== undefined && before !== r[8]) handoffLog.push([r[0], before, r[8], frame]);
  }
  lastOwner = new Map(rows.map((r) => [r[0], r[8]]));
  while (handoffLog.length > 100) handoffLog.shift();
  if (frame % 300 === 0) timeLost += 0.0167;
}

function workerStats() {
  const stats = [1, 2].map((id) => ({ id, sectors: id === 1 ? 4 : 6, bodies: 0, ghosts: 0, clones: 0, awake: 0 }));
  for (const r of rows) {
    const w = stats[r[8] - 1];
    w.bodies += 1;
    w.awake += r[9];
    w.clones += r[10];
    if (r[10]) stats[2 - r[8]].ghosts += 1;
  }
  return stats;
}

// ---------------------------------------------------------------------------------------------
// Streams.
const clients = new Set();

function send(res, name, data) {
  res.write(`event: ${name}\ndata: ${JSON.stringify(data)}\n\n`);
}

function world() {
  return { sector_size: L, hysteresis: 0.0625, region: opts.region ? { lo: [0, -1, -1], hi: [1, 0, 0] } : null, workers: [1, 2] };
}

function sendFrame(c) {
  const now = new Map(rows.map((r) => [r[0], r]));
  const fresh = rows.filter((r) => !c.known.has(r[0])).map((r) => kindById.get(r[0]));
  if (fresh.length) {
    send(c.res, 'kinds', { bodies: fresh });
    for (const k of fresh) c.known.add(k.id);
  }
  // The first frame of a connection, and one in 150 after, holds every body.
  const every = c.count % 150 === 0;
  let bodies, departed = [];
  if (every) {
    bodies = rows;
  } else {
    bodies = rows.filter((r) => c.sent.get(r[0]) !== JSON.stringify(r));
    departed = Array.from(c.sent.keys()).filter((id) => !now.has(id));
  }
  c.sent = new Map(rows.map((r) => [r[0], JSON.stringify(r)]));
  // The page forgets a departed body's kind (lpss-view's feed does the same): one that comes back is sent
  // its kind again. Kept, the blinking body's return after 5 s reached the page without its kind.
  for (const id of Array.from(c.known)) if (!now.has(id)) c.known.delete(id);
  const handoffs = handoffLog.filter((h) => h[3] > c.lastFrame);
  send(c.res, 'frame', { frame, every_body: every, bodies, departed, handoffs, workers: workerStats(),
    time_lost: timeLost, started_ms: startedMs });
  c.lastFrame = frame;
  c.count += 1;
}

function openStream(req, res) {
  res.writeHead(200, { 'Content-Type': 'text/event-stream', 'Cache-Control': 'no-cache', Connection: 'keep-alive' });
  res.write('retry: 1000\n\n');
  const c = { res, known: new Set(), sent: new Map(), lastFrame: frame, count: 0 };
  send(res, 'world', world());
  clients.add(c);
  const drop = () => clients.delete(c);
  req.on('close', drop);
  res.on('error', drop);
}

const server = http.createServer((req, res) => {
  const url = new URL(req.url, 'http://127.0.0.1');
  if (req.method !== 'GET' && req.method !== 'HEAD') { res.writeHead(405); res.end(); return; }
  if (url.pathname === '/events') { openStream(req, res); return; }
  const f = FILES[url.pathname];
  if (!f) { res.writeHead(404, { 'Content-Type': 'text/plain' }); res.end('not found\n'); return; }
  const file = path.join(f[0], f[1]);
  fs.readFile(file, (err, body) => {
    if (err) { res.writeHead(404, { 'Content-Type': 'text/plain' }); res.end(`cannot read ${file}\n`); return; }
    res.writeHead(200, { 'Content-Type': TYPES[path.extname(file)] || 'application/octet-stream', 'Cache-Control': 'no-store' });
    res.end(req.method === 'HEAD' ? undefined : body);
  });
});

const simTimer = setInterval(step, 1000 / SIM_HZ);
let tick = 0;
const sendTimer = setInterval(() => {
  tick += 1;
  if (tick % 47 === 0) return;   // a longer gap now and then: the page must not count on every frame
  for (const c of clients) {
    try { sendFrame(c); } catch (err) { clients.delete(c); }
  }
}, 1000 / opts.rate);
const pingTimer = setInterval(() => { for (const c of clients) c.res.write(': keepalive\n\n'); }, 15000);

server.listen(opts.port, '127.0.0.1', () => {
  console.log(`fake_stream: listening on http://127.0.0.1:${server.address().port}/`);
});
server.on('error', (err) => { console.error(`fake_stream: ${err.message}`); process.exit(1); });

function stop() {
  clearInterval(simTimer); clearInterval(sendTimer); clearInterval(pingTimer);
  for (const c of clients) c.res.end();
  server.close(() => process.exit(0));
  setTimeout(() => process.exit(0), 500).unref();
}
process.on('SIGTERM', stop);
process.on('SIGINT', stop);
