// lpss-view: the running world, live, in three.js (r111, the non-module build that defines THREE).
//
// The world is far larger than a float can hold, and WebGL draws in floats. So no global coordinate
// ever reaches three.js: every position is kept in JS doubles, the scene is drawn relative to an
// `origin` (doubles) kept near the camera's target, and the origin is moved (every mesh and the
// camera shifted by the same double difference) when the target strays too far from it.
//
// Protocol (server-sent events on `events`): `world`, `kinds`, `frame`; see tests/view/fake_stream.js.
(function () {
  'use strict';

  // Origin re-based once the camera target is this far from it: the GPU gets (global - origin) as
  // float32 model-view translations, good to ~1e-3 at 1e4.
  const REBASE_DISTANCE = 1e4;
  // Bodies this far from the origin are not drawn: float32 cannot place them within a unit, and they
  // are beyond any useful far plane of a view centred here.
  const HIDE_DISTANCE = 1e8;
  // The first view frames the bodies within this distance of their median, so that one body 1e12
  // out does not shrink everything else to nothing.
  const CLUSTER_RADIUS = 1e4;
  const HANDOFF_MS = 1200;          // how long a handoff marker stays
  const HANDOFF_LIST = 8;           // handoffs listed in the panel
  const MAX_MARKERS = 256;          // a burst of handoffs cannot flood the scene
  const MAX_ERRORS = 50;
  const GRID_MAX_HALF = 6;          // sector borders drawn on each side of the target's sector, per axis
  const PANEL_MS = 250;             // panel and dataset refresh

  const errors = [];
  function report(what, err) {
    const text = what + ': ' + (err && err.message ? err.message : String(err));
    if (errors.length < MAX_ERRORS) errors.push(text);
    console.error('lpss-view ' + text);
  }
  window.addEventListener('error', (e) => report('uncaught', e.error || e.message));
  window.addEventListener('unhandledrejection', (e) => report('unhandled rejection', e.reason));

  if (typeof THREE === 'undefined') {
    // Without three.js there is nothing to draw, but a test should still read why.
    report('three.js', 'THREE is not defined (three/three.min.js did not load)');
    window.lpssView = { connected: false, frame: null, framesSeen: 0, bodies: 0, meshes: [], origin: [0, 0, 0],
      workers: {}, errors, body: () => null, goTo: () => false };
    return;
  }

  const params = new URLSearchParams(location.search);
  const $ = (id) => document.getElementById(id);

  // ---------------------------------------------------------------------------------------------
  // Colours: a stable palette by worker id (Tableau 10), then golden-ratio hues past it.
  const PALETTE = [0x4e79a7, 0xf28e2b, 0x59a14f, 0xe15759, 0x76b7b2, 0xedc948, 0xb07aa1, 0xff9da7, 0x9c755f, 0xbab0ac];
  function workerColor(id) {
    if (!Number.isInteger(id) || id <= 0) return new THREE.Color(0x8a8f96);
    if (id <= PALETTE.length) return new THREE.Color(PALETTE[id - 1]);
    return new THREE.Color().setHSL((id * 0.6180339887) % 1, 0.65, 0.58);
  }
  const DIM_TOWARD = new THREE.Color(0x1c2026);

  const materials = new Map();   // shared by every body of one (worker, awake, plane?)
  function bodyMaterial(worker, awake, plane) {
    const key = worker + '|' + awake + '|' + (plane ? 'p' : 'b');
    let m = materials.get(key);
    if (m) return m;
    const color = workerColor(worker);
    // Sleeping bodies dimmed; not planes, which are static and so always asleep.
    if (!awake && !plane) color.lerp(DIM_TOWARD, 0.6);
    if (plane) {
      m = new THREE.MeshBasicMaterial({ color, transparent: true, opacity: 0.12, side: THREE.DoubleSide,
        depthWrite: false });
    } else {
      m = new THREE.MeshLambertMaterial({ color });
    }
    materials.set(key, m);
    return m;
  }
  // A clone is outlined by a halo: its own shape, a little larger, drawn from the back faces only, so
  // that the body shows through it with a light rim around it (a wireframe hides round bodies).
  const cloneMaterial = new THREE.MeshBasicMaterial({ color: 0xf4f1d0, side: THREE.BackSide });
  const planeLineMaterial = new THREE.LineBasicMaterial({ color: 0xaab4bf, transparent: true, opacity: 0.15 });

  // ---------------------------------------------------------------------------------------------
  // Shapes. One geometry per kind, shared by the meshes; `radius` bounds the shape (framing, go-to).
  const num = (v, d) => (typeof v === 'number' && Number.isFinite(v) ? v : d);
  const vec3 = (v, d) => (Array.isArray(v) && v.length >= 3 ? [num(v[0], d[0]), num(v[1], d[1]), num(v[2], d[2])] : d);

  function capsuleGeometry(r, h) {
    // Lathe around body y: the bottom hemisphere, then the top one; height = distance between the
    // hemisphere centres. Points run bottom to top so the faces look outward.
    const pts = [];
    const n = 10;
    for (let i = 0; i <= n; ++i) {
      const a = -Math.PI / 2 + (i / n) * (Math.PI / 2);
      pts.push(new THREE.Vector2(r * Math.cos(a), -h / 2 + r * Math.sin(a)));
    }
    for (let i = 0; i <= n; ++i) {
      const a = (i / n) * (Math.PI / 2);
      pts.push(new THREE.Vector2(r * Math.cos(a), h / 2 + r * Math.sin(a)));
    }
    return new THREE.LatheBufferGeometry(pts, 24);
  }

  // Used when examples' ConvexGeometry is missing or fails (e.g. coplanar points): every triangle
  // of points with all others on one side is a face. O(n^4), so only for small point sets.
  function bruteHull(vs) {
    const out = [];
    const n = vs.length;
    const e = new THREE.Vector3(), f = new THREE.Vector3(), nrm = new THREE.Vector3(), d = new THREE.Vector3();
    let scale = 0;
    for (const v of vs) scale = Math.max(scale, v.length());
    const eps = 1e-9 * Math.max(scale, 1);
    for (let i = 0; i < n; ++i) for (let j = i + 1; j < n; ++j) for (let k = j + 1; k < n; ++k) {
      e.subVectors(vs[j], vs[i]); f.subVectors(vs[k], vs[i]); nrm.crossVectors(e, f);
      const len = nrm.length();
      if (len < eps * eps) continue;
      nrm.divideScalar(len);
      let above = false, below = false;
      for (let m = 0; m < n && !(above && below); ++m) {
        if (m === i || m === j || m === k) continue;
        const s = nrm.dot(d.subVectors(vs[m], vs[i]));
        if (s > eps) above = true; else if (s < -eps) below = true;
      }
      if (!above) out.push(vs[i], vs[j], vs[k]);      // all on the back side: the normal points out
      if (!below) out.push(vs[i], vs[k], vs[j]);      // (both for a flat hull: seen from either side)
    }
    const g = new THREE.BufferGeometry();
    const a = new Float32Array(out.length * 3);
    out.forEach((v, idx) => { a[idx * 3] = v.x; a[idx * 3 + 1] = v.y; a[idx * 3 + 2] = v.z; });
    g.setAttribute('position', new THREE.BufferAttribute(a, 3));
    g.computeVertexNormals();
    return g;
  }

  function hullGeometry(points) {
    const vs = (Array.isArray(points) ? points : []).map((p) => new THREE.Vector3(...vec3(p, [0, 0, 0])));
    if (vs.length < 3) return new THREE.OctahedronBufferGeometry(0.25);
    if (vs.length >= 4 && typeof THREE.ConvexBufferGeometry === 'function' && typeof THREE.ConvexHull === 'function') {
      try {
        const g = new THREE.ConvexBufferGeometry(vs);
        if (g.attributes.position && g.attributes.position.count >= 12) return g;
      } catch (err) { /* degenerate set: fall through */ }
    }
    if (vs.length <= 64) return bruteHull(vs);
    const box = new THREE.Box3().setFromPoints(vs);
    const size = box.getSize(new THREE.Vector3()), c = box.getCenter(new THREE.Vector3());
    return new THREE.BoxBufferGeometry(size.x, size.y, size.z).translate(c.x, c.y, c.z);
  }

  const unknownShapes = new Set();
  function prepareKind(kind) {
    // Fills kind.geometry and kind.radius once; planes get their own patch (see updatePlane).
    if (kind.geometry || kind.shape === 'plane') return kind;
    let g, r;
    switch (kind.shape) {
      case 'sphere':
        r = Math.max(num(kind.radius, 0.5), 1e-6);
        g = new THREE.SphereBufferGeometry(r, 24, 16);
        break;
      case 'box': {
        const h = vec3(kind.half, [0.5, 0.5, 0.5]).map((x) => Math.max(Math.abs(x), 1e-6));
        g = new THREE.BoxBufferGeometry(2 * h[0], 2 * h[1], 2 * h[2]);
        r = Math.hypot(h[0], h[1], h[2]);
        break;
      }
      case 'capsule': {
        const cr = Math.max(num(kind.radius, 0.5), 1e-6), ch = Math.max(num(kind.height, 1), 0);
        g = capsuleGeometry(cr, ch);
        r = cr + ch / 2;
        break;
      }
      case 'hull':
        g = hullGeometry(kind.points);
        g.computeBoundingSphere();
        r = 0;
        for (const p of (Array.isArray(kind.points) ? kind.points : [])) r = Math.max(r, Math.hypot(...vec3(p, [0, 0, 0])));
        r = Math.max(r, 0.25);
        break;
      default:
        if (kind !== UNKNOWN_KIND && !unknownShapes.has(kind.shape)) {
          unknownShapes.add(kind.shape);
          report('kinds', 'unknown shape "' + kind.shape + '" (drawn as a small octahedron)');
        }
        g = new THREE.OctahedronBufferGeometry(0.5);
        r = 0.5;
    }
    kind.geometry = g;
    kind.radius = r;
    return kind;
  }
  const UNKNOWN_KIND = { id: -1, name: '', shape: 'unknown-kind', mass: 1 };

  // ---------------------------------------------------------------------------------------------
  // Scene.
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x111418);
  const camera = new THREE.PerspectiveCamera(50, window.innerWidth / Math.max(window.innerHeight, 1), 0.01, 1e5);
  scene.add(camera);
  // Light fixed to the camera (child of it, target too), so shading works for any gravity axis.
  const camLight = new THREE.DirectionalLight(0xffffff, 0.75);
  camLight.position.set(0.6, 1.0, 0.3);
  const camLightTarget = new THREE.Object3D();
  camLightTarget.position.set(0, 0, -1);
  camera.add(camLight, camLightTarget);
  camLight.target = camLightTarget;
  const hemi = new THREE.HemisphereLight(0xdde6ff, 0x303034, 0.55);
  scene.add(hemi);

  const bodyGroup = new THREE.Group();
  const markerGroup = new THREE.Group();
  scene.add(bodyGroup, markerGroup);

  let renderer = null;
  try {
    // No logarithmicDepthBuffer: without EXT_frag_depth (SwiftShader here) three.js writes it per
    // vertex, and long lines that pass behind the camera (plane grids, sector borders) vanish.
    // Near and far follow the camera distance instead (updateClip).
    renderer = new THREE.WebGLRenderer({ antialias: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setSize(window.innerWidth, window.innerHeight);
    $('view').appendChild(renderer.domElement);
  } catch (err) {
    report('WebGL', err);   // state (bodies, frames) is still kept, so tests can still read it
  }

  let controls = null;
  function makeControls() {
    // OrbitControls (r111) takes camera.up once, when made: a new up axis needs new controls.
    const target = controls ? controls.target.clone() : new THREE.Vector3();
    if (controls) controls.dispose();
    controls = null;
    if (typeof THREE.OrbitControls !== 'function') { report('controls', 'THREE.OrbitControls did not load'); return; }
    controls = new THREE.OrbitControls(camera, renderer ? renderer.domElement : document.body);
    controls.target.copy(target);
    controls.screenSpacePanning = true;
    controls.enableKeys = false;
    controls.minDistance = 1e-3;
    controls.maxDistance = 1e13;
    controls.addEventListener('start', () => { userMoved = true; });
    controls.update();
  }
  // The orbit target, relative to the origin (what OrbitControls turns around).
  const fallbackTarget = new THREE.Vector3();
  const target = () => (controls ? controls.target : fallbackTarget);

  const AXES = { x: [1, 0, 0], y: [0, 1, 0], z: [0, 0, 1], '-x': [-1, 0, 0], '-y': [0, -1, 0], '-z': [0, 0, -1] };
  let upAxis = 'y';
  function setUp(axis) {
    if (!AXES[axis]) return;
    upAxis = axis;
    camera.up.set(...AXES[axis]);
    hemi.position.set(...AXES[axis]);
    $('t-up').value = axis;
    camera.lookAt(target());
    makeControls();
  }
  // A viewing direction (from target to camera) that is not along any axis, tilted toward up.
  function defaultViewDir() {
    const up = new THREE.Vector3(...AXES[upAxis]);
    const a = new THREE.Vector3(1, 0, 0), b = new THREE.Vector3(0, 0, 1);
    if (Math.abs(up.x) > 0.5) a.set(0, 1, 0);
    if (Math.abs(up.z) > 0.5) b.set(0, 1, 0);
    return a.multiplyScalar(1.0).addScaledVector(b, 1.3).addScaledVector(up, 0.9).normalize();
  }

  // ---------------------------------------------------------------------------------------------
  // State, all global positions in doubles.
  const origin = [0, 0, 0];
  let world = null;                 // last `world` event
  const kinds = new Map();          // id -> kind
  const kindText = new Map();       // id -> the kind's JSON as received
  const bodies = new Map();         // id -> {id, kind, g:[x,y,z], q:[x,y,z,w], worker, awake, cloned, mesh, outline}
  let workerStats = [];
  let timeLost = null, startedMs = null;
  let frameNo = null, framesSeen = 0;
  const frameTimes = [];            // [ms, frame] of recent frame events, for the rates
  const renderTimes = [];           // ms of recent renders
  const handoffs = [];              // latest first: {body, from, to, frame}
  const markers = [];               // {mesh, body, born}
  let connected = false;
  let userMoved = false, framed = false;
  let pendingGoto = params.get('goto');
  // ?frames=K: stop listening after K frames. For `chromium --dump-dom --virtual-time-budget`, whose
  // virtual clock does not run while a request (the event stream) is open.
  const maxFrames = params.has('frames') ? Number(params.get('frames')) : Infinity;
  let stream = null;
  let followId = params.has('follow') ? params.get('follow') : null;
  const show = { grid: true, clones: false, handoffs: true };
  const missingKinds = new Set();
  let upChosen = false;             // the user picked an up axis: a world's gravity does not override it

  function placeMesh(rec) {
    const m = rec.mesh;
    // The double subtraction is the floating origin: the result is small near the camera.
    m.position.set(rec.g[0] - origin[0], rec.g[1] - origin[1], rec.g[2] - origin[2]);
    const far = Math.max(Math.abs(m.position.x), Math.abs(m.position.y), Math.abs(m.position.z)) > HIDE_DISTANCE;
    m.visible = !far;
  }

  function setOrigin(o) {
    origin[0] = o[0]; origin[1] = o[1]; origin[2] = o[2];
    // Recomputed from the doubles, never shifted: shifts would accumulate rounding.
    for (const rec of bodies.values()) if (!rec.plane) placeMesh(rec);
    gridKey = '';
    buildRegion();
  }

  function makeMesh(rec) {
    if (rec.plane) {
      const mesh = new THREE.Mesh(planeQuad, bodyMaterial(rec.worker, rec.awake, true));
      // The fill reaches PLANE_FILL times further than the grid lines.
      const grid = new THREE.LineSegments(planeGrid, planeLineMaterial);
      grid.scale.set(1 / PLANE_FILL, 1 / PLANE_FILL, 1);
      mesh.add(grid);
      mesh.renderOrder = -1;   // translucent: behind the bodies
      return mesh;
    }
    const mesh = new THREE.Mesh(rec.kind.geometry, bodyMaterial(rec.worker, rec.awake, false));
    return mesh;
  }

  function addBody(id) {
    let kind = kinds.get(id);
    if (!kind) {
      if (!missingKinds.has(id)) { missingKinds.add(id); report('frame', 'body ' + id + ' came before its kinds'); }
      kind = UNKNOWN_KIND;
    }
    prepareKind(kind);
    const rec = { id, kind, g: [0, 0, 0], q: [0, 0, 0, 1], worker: -1, awake: 1, cloned: 0, mesh: null, outline: null,
      plane: kind.shape === 'plane' };
    rec.mesh = makeMesh(rec);
    rec.mesh.userData.bodyId = id;
    bodyGroup.add(rec.mesh);
    bodies.set(id, rec);
    return rec;
  }

  // forget: the body left the world, so its kind (and that kind's geometry, made for it alone) goes too; a
  // world that keeps spawning and removing bodies does not grow the page.
  function removeBody(id, forget) {
    const rec = bodies.get(id);
    if (rec) {
      bodyGroup.remove(rec.mesh);
      bodies.delete(id);
    }
    if (!forget) return;
    const kind = kinds.get(id);
    if (kind && kind.geometry) kind.geometry.dispose();
    kinds.delete(id);
    kindText.delete(id);
    missingKinds.delete(id);
  }

  function setOutline(rec) {
    const want = show.clones && rec.cloned && !rec.plane;
    if (want && !rec.outline) {
      rec.outline = new THREE.Mesh(rec.kind.geometry, cloneMaterial);
      rec.outline.scale.setScalar(1.18);
      rec.mesh.add(rec.outline);
    }
    if (rec.outline) rec.outline.visible = !!want;
  }

  function applyRow(row) {
    if (!Array.isArray(row) || row.length < 8) { report('frame', 'bad body row ' + JSON.stringify(row)); return; }
    const id = row[0];
    const rec = bodies.get(id) || addBody(id);
    rec.g[0] = row[1]; rec.g[1] = row[2]; rec.g[2] = row[3];
    rec.q[0] = row[4]; rec.q[1] = row[5]; rec.q[2] = row[6]; rec.q[3] = row[7];
    const worker = row.length > 8 ? row[8] : -1;
    const awake = row.length > 9 ? (row[9] ? 1 : 0) : 1;
    const cloned = row.length > 10 ? (row[10] ? 1 : 0) : 0;
    if (worker !== rec.worker || awake !== rec.awake) {
      rec.worker = worker; rec.awake = awake;
      rec.mesh.material = bodyMaterial(worker, awake, rec.plane);
    }
    rec.cloned = cloned;
    if (!rec.plane) {
      placeMesh(rec);
      rec.mesh.quaternion.set(rec.q[0], rec.q[1], rec.q[2], rec.q[3]);
      setOutline(rec);
    }
  }

  // ---------------------------------------------------------------------------------------------
  // Events.
  function onWorld(m) {
    world = m;
    if (!(num(m.sector_size, 0) > 0)) report('world', 'sector_size missing or not positive');
    // Not in the protocol yet; if a server sends gravity, look with "up" against it (unless chosen).
    if (Array.isArray(m.gravity) && !params.has('up') && !upChosen) {
      const g = vec3(m.gravity, [0, 0, 0]);
      const i = [0, 1, 2].reduce((b, k) => (Math.abs(g[k]) > Math.abs(g[b]) ? k : b), 0);
      if (g[i] !== 0) setUp((g[i] > 0 ? '-' : '') + 'xyz'[i]);
    }
    gridKey = '';
    buildRegion();
  }

  function onKinds(m) {
    for (const k of (m && Array.isArray(m.bodies) ? m.bodies : [])) {
      if (typeof k.id !== 'string') { report('kinds', 'kind without an id'); continue; }
      // The same description again (a reconnection): keep the kind and its geometry.
      const text = JSON.stringify(k);
      if (kindText.get(k.id) === text) continue;
      kindText.set(k.id, text);
      kinds.set(k.id, k);
      const rec = bodies.get(k.id);
      if (rec) {
        // A new description of a body we draw (e.g. a restarted server): rebuild its mesh in place.
        const keep = rec;
        removeBody(k.id);
        const fresh = addBody(k.id);
        fresh.g = keep.g; fresh.q = keep.q;
        applyRow([k.id, ...keep.g, ...keep.q, keep.worker, keep.awake, keep.cloned]);
      }
    }
  }

  function onFrame(m) {
    const rows = Array.isArray(m.bodies) ? m.bodies : [];
    if (m.every_body) {
      const seen = new Set();
      for (const row of rows) { applyRow(row); if (Array.isArray(row)) seen.add(row[0]); }
      for (const id of Array.from(bodies.keys())) if (!seen.has(id)) removeBody(id, true);
    } else {
      for (const row of rows) applyRow(row);
      for (const id of (Array.isArray(m.departed) ? m.departed : [])) removeBody(id, true);
    }
    for (const h of (Array.isArray(m.handoffs) ? m.handoffs : [])) onHandoff(h);
    if (Array.isArray(m.workers)) workerStats = m.workers;
    if (m.time_lost !== undefined) timeLost = m.time_lost;
    if (m.started_ms !== undefined) startedMs = m.started_ms;
    frameNo = m.frame;
    framesSeen += 1;
    const now = performance.now();
    frameTimes.push([now, m.frame]);
    while (frameTimes.length > 2 && now - frameTimes[0][0] > 2000) frameTimes.shift();

    if (!framed && !userMoved) framed = frameAll();
    if (pendingGoto !== null && goTo(pendingGoto)) pendingGoto = null;
    if (framesSeen >= maxFrames && stream) { stream.close(); stream = null; connected = false; }
  }

  function onHandoff(h) {
    if (!Array.isArray(h) || h.length < 3) { report('frame', 'bad handoff ' + JSON.stringify(h)); return; }
    const [body, from, to, frame] = h;
    handoffs.unshift({ body, from, to, frame });
    if (handoffs.length > HANDOFF_LIST) handoffs.length = HANDOFF_LIST;
    const rec = bodies.get(body);
    if (!show.handoffs || !rec || rec.plane || markers.length >= MAX_MARKERS) return;
    const mesh = new THREE.Mesh(ringGeometry, new THREE.MeshBasicMaterial({ color: workerColor(to), transparent: true,
      side: THREE.DoubleSide, depthTest: false }));
    mesh.renderOrder = 10;   // on top: a ring hidden behind its own body would be useless
    markerGroup.add(mesh);
    markers.push({ mesh, body, born: performance.now(), size: 1.6 * rec.kind.radius });
  }
  const ringGeometry = new THREE.RingBufferGeometry(0.85, 1.0, 48);

  // Body ids are 64-bit: the server sends them as strings (a JSON number loses digits past 2^53), and the
  // page keys everything by the string. Numbers (from an older or a test server) are turned into strings.
  function stringIds(name, m) {
    if (!m) return m;
    if (name === 'kinds' && Array.isArray(m.bodies)) {
      for (const k of m.bodies) if (k && (typeof k.id === 'number' || typeof k.id === 'string')) k.id = String(k.id);
    }
    if (name === 'frame') {
      for (const row of (Array.isArray(m.bodies) ? m.bodies : [])) if (Array.isArray(row)) row[0] = String(row[0]);
      if (Array.isArray(m.departed)) m.departed = m.departed.map(String);
      for (const h of (Array.isArray(m.handoffs) ? m.handoffs : [])) if (Array.isArray(h)) h[0] = String(h[0]);
    }
    return m;
  }

  function connect() {
    if (typeof EventSource !== 'function') { report('events', 'EventSource is not supported'); return; }
    // ?rate=N asks the server for at most N frames a second (it sends at most its --max-rate anyway): a
    // page on a slow machine need not be sent more than it draws.
    const rate = Number(params.get('rate'));
    const eventsUrl = (params.get('events') || 'events') + (rate > 0 ? '?rate=' + rate : '');
    const es = new EventSource(eventsUrl);
    stream = es;
    const on = (name, fn) => es.addEventListener(name, (e) => {
      let m;
      try { m = JSON.parse(e.data); } catch (err) {
        // Frames are deltas: one lost event would leave the page wrong until the next full frame. Start
        // the stream again, which begins with every body.
        report(name, 'bad JSON: ' + err.message + '; reconnecting');
        es.close();
        if (stream === es) { stream = null; connected = false; setTimeout(connect, 500); }
        return;
      }
      try { fn(stringIds(name, m)); } catch (err) { report(name, err); }
    });
    es.onopen = () => { connected = true; };
    // EventSource reconnects by itself; the server starts each connection with world, kinds and
    // an every_body frame, so nothing to resynchronise here.
    es.onerror = () => { connected = es.readyState === EventSource.OPEN; };
    on('world', onWorld);
    on('kinds', onKinds);
    on('frame', onFrame);
  }

  // ---------------------------------------------------------------------------------------------
  // Camera moves.
  function frameAll() {
    const recs = [];
    for (const rec of bodies.values()) if (!rec.plane) recs.push(rec);
    if (!recs.length) return false;
    const med = [0, 1, 2].map((i) => {
      const v = recs.map((r) => r.g[i]).sort((a, b) => a - b);
      return v[v.length >> 1];
    });
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (const r of recs) {
      if (Math.max(Math.abs(r.g[0] - med[0]), Math.abs(r.g[1] - med[1]), Math.abs(r.g[2] - med[2])) > CLUSTER_RADIUS) continue;
      for (let i = 0; i < 3; ++i) {
        lo[i] = Math.min(lo[i], r.g[i] - r.kind.radius);
        hi[i] = Math.max(hi[i], r.g[i] + r.kind.radius);
      }
    }
    // The centre and the origin in doubles; the camera then sits a few radii from (0, 0, 0).
    const centre = [0, 1, 2].map((i) => lo[i] + (hi[i] - lo[i]) / 2);
    const radius = Math.max(0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]), 1);
    setOrigin(centre);
    target().set(0, 0, 0);
    const dist = radius / Math.sin((camera.fov * Math.PI / 180) / 2) * 1.1;
    camera.position.copy(defaultViewDir()).multiplyScalar(dist);
    camera.lookAt(target());
    if (controls) controls.update();
    return true;
  }

  function findBody(idOrName) {
    const s = String(idOrName === undefined || idOrName === null ? '' : idOrName).trim();
    if (!s) return null;
    if (/^\d+$/.test(s)) { const r = bodies.get(s); if (r) return r; }
    for (const rec of bodies.values()) if (rec.kind.name === s) return rec;
    return null;
  }

  function anchorOf(rec) {
    // A plane's anchor: the point position + offset * normal, on the plane.
    if (!rec.plane) return rec.g.slice();
    const n = planeNormal(rec);
    const off = num(rec.kind.offset, 0);
    return [rec.g[0] + off * n.x, rec.g[1] + off * n.y, rec.g[2] + off * n.z];
  }

  function goTo(idOrName) {
    const rec = findBody(idOrName);
    if (!rec) return false;
    const dir = camera.position.clone().sub(target());
    if (dir.lengthSq() === 0 || !Number.isFinite(dir.lengthSq())) dir.copy(defaultViewDir());
    dir.normalize();
    const dist = rec.plane ? 20 : Math.max(8 * rec.kind.radius, 4);
    // The origin becomes the body's own global position: it is then drawn at exactly (0,0,0).
    setOrigin(anchorOf(rec));
    target().set(0, 0, 0);
    camera.position.copy(dir).multiplyScalar(dist);
    camera.lookAt(target());
    if (controls) controls.update();
    if (show.follow) followId = rec.id;
    userMoved = true;
    framed = true;
    return true;
  }

  function followStep() {
    if (followId === null) return;
    const rec = findBody(followId);
    if (!rec || rec.plane) return;
    const t = target();
    const dx = rec.mesh.position.x - t.x, dy = rec.mesh.position.y - t.y, dz = rec.mesh.position.z - t.z;
    t.set(rec.mesh.position.x, rec.mesh.position.y, rec.mesh.position.z);
    camera.position.x += dx; camera.position.y += dy; camera.position.z += dz;
  }

  function maybeRebase() {
    const t = target();
    if (Math.max(Math.abs(t.x), Math.abs(t.y), Math.abs(t.z)) <= REBASE_DISTANCE) return;
    const d = t.clone();
    camera.position.sub(d);
    t.set(0, 0, 0);
    setOrigin([origin[0] + d.x, origin[1] + d.y, origin[2] + d.z]);
  }

  // Lines cut in n pieces. SwiftShader (what headless chromium draws WebGL with here) drops a whole
  // line segment that reaches behind the camera instead of clipping it; in short pieces only the
  // piece under the camera goes, which is out of sight anyway.
  function pushSegmented(p, s, e, n) {
    for (let i = 0; i < n; ++i) {
      const a = i / n, b = (i + 1) / n;
      p.push(s[0] + (e[0] - s[0]) * a, s[1] + (e[1] - s[1]) * a, s[2] + (e[2] - s[2]) * a,
        s[0] + (e[0] - s[0]) * b, s[1] + (e[1] - s[1]) * b, s[2] + (e[2] - s[2]) * b);
    }
  }

  // ---------------------------------------------------------------------------------------------
  // Planes: a finite patch (translucent quad + grid) on the plane, centred on the point of the
  // plane nearest the camera target and snapped to its grid step so the grid does not swim.
  const PLANE_CELLS = 100, PLANE_FILL = 10;
  const planeQuad = new THREE.PlaneBufferGeometry(1, 1);
  const planeGrid = (() => {
    const n = PLANE_CELLS, p = [];
    for (let i = 0; i <= n; ++i) {
      const s = -0.5 + i / n;
      pushSegmented(p, [s, -0.5, 0], [s, 0.5, 0], n);
      pushSegmented(p, [-0.5, s, 0], [0.5, s, 0], n);
    }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(p, 3));
    return g;
  })();
  const _q = new THREE.Quaternion(), _m = new THREE.Matrix4();
  function planeNormal(rec) {
    // The kind's normal is in body axes (as Bullet's static plane): turn it by the orientation.
    const n = new THREE.Vector3(...vec3(rec.kind.normal, [0, 1, 0]));
    if (n.lengthSq() === 0) n.set(0, 1, 0);
    n.normalize();
    _q.set(rec.q[0], rec.q[1], rec.q[2], rec.q[3]);
    if (_q.lengthSq() > 0) n.applyQuaternion(_q.normalize());
    return n;
  }
  function updatePlane(rec) {
    const n = planeNormal(rec);
    const p0 = anchorOf(rec);
    const t = target();
    const tg = [origin[0] + t.x, origin[1] + t.y, origin[2] + t.z];
    const h = n.x * (tg[0] - p0[0]) + n.y * (tg[1] - p0[1]) + n.z * (tg[2] - p0[2]);
    // Tangents of the plane.
    const t1 = Math.abs(n.x) < 0.9 ? new THREE.Vector3(1, 0, 0) : new THREE.Vector3(0, 1, 0);
    t1.addScaledVector(n, -t1.dot(n)).normalize();
    const t2 = new THREE.Vector3().crossVectors(n, t1);
    // Grid step: a power of ten near a twentieth of the camera's distance; the grid is 100 steps
    // wide, the translucent fill ten times that.
    const dist = Math.max(camera.position.distanceTo(t), Math.abs(h), 1e-3);
    const step = Math.pow(10, Math.round(Math.log10(dist / 20)));
    const span = step * PLANE_CELLS * PLANE_FILL;
    const c = [tg[0] - h * n.x - p0[0], tg[1] - h * n.y - p0[1], tg[2] - h * n.z - p0[2]];
    const u = Math.round((c[0] * t1.x + c[1] * t1.y + c[2] * t1.z) / step) * step;
    const v = Math.round((c[0] * t2.x + c[1] * t2.y + c[2] * t2.z) / step) * step;
    const m = rec.mesh;
    m.position.set(p0[0] + u * t1.x + v * t2.x - origin[0], p0[1] + u * t1.y + v * t2.y - origin[1],
      p0[2] + u * t1.z + v * t2.z - origin[2]);
    m.quaternion.setFromRotationMatrix(_m.makeBasis(t1, t2, n));
    m.scale.set(span, span, 1);
    m.visible = Math.abs(h) < HIDE_DISTANCE;
  }

  // ---------------------------------------------------------------------------------------------
  // Sector borders: lines at (n + 1/2) * sector_size on each axis, in a block of sectors around the
  // camera target; rebuilt only when that block or the origin changes.
  const gridMaterial = new THREE.LineBasicMaterial({ color: 0x6fa8dc, transparent: true, opacity: 0.6 });
  const gridLines = new THREE.LineSegments(new THREE.BufferGeometry(), gridMaterial);
  gridLines.frustumCulled = false;
  scene.add(gridLines);
  let gridKey = '';
  // The border plane nearest the target on each axis, as a faint wall within the block, so one
  // sees which side of a border a body is on (the lattice lines are only the walls' edges).
  const wallMaterial = new THREE.MeshBasicMaterial({ color: 0x8fa3b8, transparent: true, opacity: 0.07,
    side: THREE.DoubleSide, depthWrite: false });
  const walls = [0, 1, 2].map((a) => {
    const w = new THREE.Mesh(planeQuad, wallMaterial);
    if (a === 0) w.rotation.set(0, Math.PI / 2, 0);          // the quad's normal (z) turned to x
    if (a === 1) w.rotation.set(-Math.PI / 2, 0, 0);         // ... to y
    w.renderOrder = -2;
    w.visible = false;
    scene.add(w);
    return w;
  });
  let wallBorders = null;   // per axis: the border coordinates (relative), and the block's centre and size
  function updateWalls() {
    const t = target();
    const dist = camera.position.distanceTo(t);
    for (let a = 0; a < 3; ++a) {
      const w = walls[a];
      w.visible = false;
      if (!gridLines.visible || !wallBorders) continue;
      const tv = [t.x, t.y, t.z];
      let best = null;
      for (const b of wallBorders.b[a]) if (best === null || Math.abs(b - tv[a]) < Math.abs(best - tv[a])) best = b;
      if (best === null || Math.abs(best - tv[a]) > 1.5 * dist) continue;
      const pos = wallBorders.centre.slice();
      pos[a] = best;
      w.position.set(pos[0], pos[1], pos[2]);
      const a1 = (a + 1) % 3, a2 = (a + 2) % 3;
      // After the rotations above the quad's own x, y lie along world (z, y) for a = 0, (x, z) for 1, (x, y) for 2.
      const sx = a === 0 ? wallBorders.size[2] : wallBorders.size[0];
      const sy = a === 1 ? wallBorders.size[2] : wallBorders.size[1];
      w.scale.set(sx, sy, 1);
      w.visible = wallBorders.size[a1] > 0 && wallBorders.size[a2] > 0;
    }
  }
  function targetSector() {
    if (!world || !(world.sector_size > 0)) return null;
    const t = target(), L = world.sector_size;
    return [Math.round((origin[0] + t.x) / L), Math.round((origin[1] + t.y) / L), Math.round((origin[2] + t.z) / L)];
  }
  function updateGrid() {
    const c = targetSector();
    gridLines.visible = show.grid && c !== null;
    updateWalls();
    if (!gridLines.visible) return;
    const L = world.sector_size;
    const dist = camera.position.distanceTo(target());
    const m = Math.min(Math.max(Math.ceil(dist / L), 1), GRID_MAX_HALF);
    const key = c.join(',') + '|' + m + '|' + origin.join(',') + '|' + L;
    if (key === gridKey) return;
    gridKey = key;
    // Border coordinates relative to the origin, each computed in doubles from its integer index.
    const b = [0, 1, 2].map((a) => {
      const r = [];
      for (let k = -m; k < m; ++k) r.push((c[a] + k + 0.5) * L - origin[a]);
      return r;
    });
    const p = [];
    for (let a = 0; a < 3; ++a) {
      const a1 = (a + 1) % 3, a2 = (a + 2) % 3;
      const lo = b[a][0], hi = b[a][b[a].length - 1];
      for (const u of b[a1]) for (const v of b[a2]) {
        const s = [0, 0, 0], e = [0, 0, 0];
        s[a] = lo; e[a] = hi; s[a1] = e[a1] = u; s[a2] = e[a2] = v;
        pushSegmented(p, s, e, Math.max(1, Math.round((hi - lo) / L) * 4));
      }
    }
    gridLines.geometry.dispose();
    gridLines.geometry = new THREE.BufferGeometry();
    gridLines.geometry.setAttribute('position', new THREE.Float32BufferAttribute(p, 3));
    wallBorders = { b, centre: b.map((r) => (r[0] + r[r.length - 1]) / 2), size: b.map((r) => r[r.length - 1] - r[0]) };
    updateWalls();
  }

  // The region a server was started with (--region), as a box of sector bounds.
  const regionLines = new THREE.LineSegments(new THREE.BufferGeometry(),
    new THREE.LineBasicMaterial({ color: 0xd0a040, transparent: true, opacity: 0.8 }));
  regionLines.frustumCulled = false;
  scene.add(regionLines);
  function buildRegion() {
    const r = world && world.region;
    regionLines.visible = !!(r && Array.isArray(r.lo) && Array.isArray(r.hi) && world.sector_size > 0);
    if (!regionLines.visible) return;
    const L = world.sector_size;
    // Clamped: only the part near the camera can be seen, and float32 cannot carry 1e12 anyway.
    const cl = (x) => Math.max(-HIDE_DISTANCE, Math.min(HIDE_DISTANCE, x));
    const lo = [0, 1, 2].map((a) => cl((r.lo[a] - 0.5) * L - origin[a]));
    const hi = [0, 1, 2].map((a) => cl((r.hi[a] + 0.5) * L - origin[a]));
    const p = [];
    for (let a = 0; a < 3; ++a) {
      const a1 = (a + 1) % 3, a2 = (a + 2) % 3;
      for (const u of [lo[a1], hi[a1]]) for (const v of [lo[a2], hi[a2]]) {
        const s = [0, 0, 0], e = [0, 0, 0];
        s[a] = lo[a]; e[a] = hi[a]; s[a1] = e[a1] = u; s[a2] = e[a2] = v;
        pushSegmented(p, s, e, Math.min(256, Math.max(1, Math.round((hi[a] - lo[a]) / L) * 4)));
      }
    }
    regionLines.geometry.dispose();
    regionLines.geometry = new THREE.BufferGeometry();
    regionLines.geometry.setAttribute('position', new THREE.Float32BufferAttribute(p, 3));
  }

  function updateMarkers(now) {
    for (let i = markers.length - 1; i >= 0; --i) {
      const mk = markers[i];
      const age = (now - mk.born) / HANDOFF_MS;
      const rec = bodies.get(mk.body);
      if (age >= 1 || !rec || !show.handoffs) {
        markerGroup.remove(mk.mesh);
        mk.mesh.material.dispose();
        markers.splice(i, 1);
        continue;
      }
      mk.mesh.position.copy(rec.mesh.position);
      mk.mesh.quaternion.copy(camera.quaternion);   // face the camera
      mk.mesh.scale.setScalar(mk.size * (1 + 0.8 * age));
      mk.mesh.material.opacity = 1 - age;
    }
  }

  // ---------------------------------------------------------------------------------------------
  // Rendering.
  function updateClip() {
    // Near and far follow the distance d to the target: a 24-bit depth buffer then resolves about
    // d / 17000 at the target and d / 170 at 10 d; things past 1e4 d are cut.
    const d = Math.max(camera.position.distanceTo(target()), 1e-3);
    const near = d * 1e-3, far = Math.max(d * 1e4, 1e3);
    if (Math.abs(camera.near / near - 1) > 0.2 || Math.abs(camera.far / far - 1) > 0.2) {
      camera.near = near; camera.far = far;
      camera.updateProjectionMatrix();
    }
  }

  function prepareView() {
    followStep();
    if (controls) controls.update(); else camera.lookAt(target());
    maybeRebase();
    for (const rec of bodies.values()) if (rec.plane) updatePlane(rec);
    updateGrid();
    updateClip();
    camera.updateMatrixWorld();
    camera.matrixWorldInverse.getInverse(camera.matrixWorld);
  }

  function loop(now) {
    requestAnimationFrame(loop);
    try {
      prepareView();
      updateMarkers(performance.now());
      if (renderer) renderer.render(scene, camera);
      renderTimes.push(performance.now());
      while (renderTimes.length > 2 && renderTimes[renderTimes.length - 1] - renderTimes[0] > 1000) renderTimes.shift();
    } catch (err) {
      report('render', err);
    }
  }

  function onResize() {
    const w = window.innerWidth, h = Math.max(window.innerHeight, 1);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    if (renderer) renderer.setSize(w, h);
  }
  window.addEventListener('resize', onResize);

  // ---------------------------------------------------------------------------------------------
  // Panel, and the state a test reads.
  function workerCounts() {
    const c = {};
    for (const rec of bodies.values()) c[rec.worker] = (c[rec.worker] || 0) + 1;
    return c;
  }
  function rates() {
    let world = null, events = null, page = null;
    const now = performance.now();
    const recent = frameTimes.filter((f) => now - f[0] <= 1000);
    if (recent.length) events = recent.length / 1.0;
    if (frameTimes.length >= 2) {
      const a = frameTimes[0], b = frameTimes[frameTimes.length - 1];
      if (b[0] > a[0] && now - b[0] < 2000) world = (b[1] - a[1]) / ((b[0] - a[0]) / 1000);
      else if (now - b[0] >= 2000) world = 0;
    }
    if (renderTimes.length >= 2) {
      const dt = renderTimes[renderTimes.length - 1] - renderTimes[0];
      if (dt > 0) page = (renderTimes.length - 1) / (dt / 1000);
    }
    return { world, events, page };
  }

  function bodyInfo(id) {
    const rec = findBody(id);
    if (!rec) return null;
    prepareView();   // the camera as it will be drawn next
    const p = rec.mesh.position;
    const drawnGlobal = [origin[0] + p.x, origin[1] + p.y, origin[2] + p.z];
    const cam = p.clone().applyMatrix4(camera.matrixWorldInverse);
    const ndc = p.clone().project(camera);
    const el = renderer ? renderer.domElement : null;
    const w = el ? el.clientWidth : window.innerWidth, h = el ? el.clientHeight : window.innerHeight;
    const screen = [(ndc.x + 1) / 2 * w, (1 - ndc.y) / 2 * h];
    const visible = rec.mesh.visible && cam.z < 0 && Math.abs(ndc.x) <= 1 && Math.abs(ndc.y) <= 1;
    return { id: rec.id, name: rec.kind.name || '', shape: rec.kind.shape, global: rec.g.slice(), drawnGlobal, screen,
      visible, worker: rec.worker, awake: rec.awake, cloned: rec.cloned };
  }

  const fmt = (x, d) => (x === null || x === undefined || !Number.isFinite(x) ? '-' : x.toFixed(d));
  function cell(tr, text, cls) {
    const td = document.createElement('td');
    td.textContent = text;
    if (cls) td.className = cls;
    tr.appendChild(td);
    return td;
  }
  function updatePanel() {
    const r = rates();
    const counts = workerCounts();
    $('status').textContent = connected ? 'live' : 'disconnected';
    $('status').className = connected ? 'ok' : 'bad';
    $('s-frame').textContent = frameNo === null ? '-' : String(frameNo) + '  (' + framesSeen + ' seen)';
    $('s-wfps').textContent = fmt(r.world, 1) + ' frames/s  (' + fmt(r.events, 0) + ' events/s)';
    $('s-pfps').textContent = fmt(r.page, 1) + ' fps';
    $('s-bodies').textContent = String(bodies.size);
    $('s-lost').textContent = timeLost === null ? '-' : fmt(Number(timeLost), 3) + ' s';
    $('s-running').textContent = startedMs ? fmt((Date.now() - startedMs) / 1000, 1) + ' s' : '-';
    const sec = targetSector();
    $('s-sector').textContent = sec ? '[' + sec.join(', ') + ']' + (world.sector_size ? '  L=' + world.sector_size : '') : '-';
    $('s-origin').textContent = origin.map((x) => x.toPrecision(17).replace(/\.?0+$/, '')).join(', ');

    // Workers: those in the stats, the assignment, and any that own a drawn body.
    const ids = new Set();
    for (const w of workerStats) ids.add(w.id);
    for (const w of ((world && world.workers) || [])) ids.add(w);
    for (const k of Object.keys(counts)) ids.add(Number(k));
    const tbody = $('s-workers');
    tbody.textContent = '';
    for (const id of Array.from(ids).sort((a, b) => a - b)) {
      const w = workerStats.find((s) => s.id === id) || {};
      const tr = document.createElement('tr');
      const td = cell(tr, '');
      const sw = document.createElement('span');
      sw.className = 'swatch';
      sw.style.background = '#' + workerColor(id).getHexString();
      td.append(sw, String(id));
      for (const v of [w.sectors, w.bodies, counts[id] || 0, w.ghosts, w.clones, w.awake]) cell(tr, v === undefined ? '-' : String(v));
      tbody.appendChild(tr);
    }

    const ol = $('s-handoffs');
    ol.textContent = '';
    for (const h of handoffs) {
      const li = document.createElement('li');
      const rec = bodies.get(h.body);
      const name = rec && rec.kind.name ? ' ' + rec.kind.name : '';
      li.textContent = 'frame ' + h.frame + ': body ' + h.body + name + '  ' + h.from + ' \u2192 ' + h.to;
      ol.appendChild(li);
    }
    $('s-errors').textContent = errors.slice(-3).join('\n');

    // The same summary in the DOM, for `chromium --dump-dom` and anything that cannot run JS.
    const ds = document.body.dataset;
    ds.connected = connected ? '1' : '0';
    ds.frame = frameNo === null ? '' : String(frameNo);
    ds.framesSeen = String(framesSeen);
    ds.bodies = String(bodies.size);
    ds.workers = JSON.stringify(counts);
    ds.origin = origin.join(',');
    ds.errors = String(errors.length);
    document.title = 'lpss-view \u00b7 frame ' + (frameNo === null ? '-' : frameNo) + ' \u00b7 ' + bodies.size + ' bodies';
  }

  // ---------------------------------------------------------------------------------------------
  // Inputs.
  $('goto-form').addEventListener('submit', (e) => {
    e.preventDefault();
    const v = $('goto-input').value;
    const ok = goTo(v);
    $('goto-result').textContent = ok ? 'at body ' + findBody(v).id : 'no body "' + v + '"';
  });
  $('frame-all').addEventListener('click', () => { followId = null; frameAll(); });
  $('t-grid').addEventListener('change', (e) => { show.grid = e.target.checked; });
  $('t-clones').addEventListener('change', (e) => {
    show.clones = e.target.checked;
    for (const rec of bodies.values()) setOutline(rec);
  });
  $('t-handoffs').addEventListener('change', (e) => { show.handoffs = e.target.checked; });
  $('t-follow').addEventListener('change', (e) => {
    show.follow = e.target.checked;
    if (!show.follow) followId = null;
    else { const v = $('goto-input').value.trim(); if (v && findBody(v)) followId = findBody(v).id; }
  });
  $('t-up').addEventListener('change', (e) => { upChosen = true; setUp(e.target.value); });
  if (followId !== null) { show.follow = true; $('t-follow').checked = true; }

  window.lpssView = {
    get connected() { return connected; },
    get frame() { return frameNo; },
    get framesSeen() { return framesSeen; },
    get bodies() { return bodies.size; },
    get meshes() { return Array.from(bodies.values(), (r) => r.mesh); },
    get origin() { return origin.slice(); },
    get workers() { return workerCounts(); },
    get rates() { return rates(); },
    get handoffs() { return handoffs.slice(); },
    get world() { return world; },
    errors,
    body: bodyInfo,
    goTo,
    frameAll,
    three: { scene, camera, get controls() { return controls; }, renderer },
  };

  setUp(AXES[params.get('up')] ? params.get('up') : 'y');
  camera.position.copy(defaultViewDir()).multiplyScalar(20);
  camera.lookAt(target());
  if (controls) controls.update();
  connect();
  setInterval(() => { try { updatePanel(); } catch (err) { report('panel', err); } }, PANEL_MS);
  updatePanel();
  requestAnimationFrame(loop);
})();
