#!/usr/bin/env node
// Opens lpss-view's page in Debian's chromium (headless, WebGL through SwiftShader), waits until it
// has seen the world, optionally goes to a body, takes a screenshot and prints one JSON line with
// what the page holds. Exit 0 when it got there, 1 with a message otherwise (the JSON line is
// printed either way, with "ok" and "message").
//
//   node tests/view/check_page.js --url http://127.0.0.1:PORT/ --screenshot OUT.png
//        [--goto ID|NAME] [--expect-bodies N] [--min-frames K] [--timeout-s T]
//        [--expect-at X,Y,Z] [--tolerance U] [--size WxH] [--chromium PATH] [--allow-errors]
//
// --expect-bodies N  waits until the page draws exactly N bodies.
// --goto ID          calls lpssView.goTo(ID) once the frames are in, waits a few frames, and then
//                    requires the body visible and drawn where the page was told it is
//                    (|origin + mesh.position - global| <= U on each axis, U = --tolerance, 1e-3);
//                    --expect-at also compares that drawn position with X,Y,Z.
// Errors: uncaught page errors, lpssView.errors and HTTP responses >= 400 fail the check unless
// --allow-errors; console errors are only reported.
//
// The browser is started here (not by puppeteer) in its own process group, so that every path out
// (done, failure, timeout, SIGTERM/SIGINT/SIGHUP, an exception) kills all of it, and its profile
// directory is removed.
'use strict';

const { spawn } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');

function loadPuppeteer() {
  // The copy pinned by tests/node/package-lock.json first, then NODE_PATH.
  try { return require(path.join(__dirname, '../node/node_modules/puppeteer-core')); } catch (e) { /* next */ }
  return require('puppeteer-core');
}

function usage(msg) {
  if (msg) console.error(`check_page: ${msg}`);
  console.error('usage: node tests/view/check_page.js --url URL --screenshot OUT.png [--goto ID] [--expect-bodies N]\n' +
    '         [--min-frames K] [--timeout-s T] [--expect-at X,Y,Z] [--tolerance U] [--size WxH] [--chromium PATH] [--allow-errors]');
  process.exit(2);
}

function parseArgs(argv) {
  const o = { url: null, screenshot: null, goto: null, expectBodies: null, minFrames: 1, timeoutS: 30,
    expectAt: null, tolerance: 1e-3, width: 1280, height: 800, chromium: '/usr/bin/chromium', allowErrors: false };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    const next = () => { if (i + 1 >= argv.length) usage(`${a} needs a value`); return argv[++i]; };
    const number = (v, what) => { const n = Number(v); if (!Number.isFinite(n)) usage(`${what}: not a number: ${v}`); return n; };
    switch (a) {
      case '--url': o.url = next(); break;
      case '--screenshot': o.screenshot = path.resolve(next()); break;
      case '--goto': o.goto = next(); break;
      case '--expect-bodies': o.expectBodies = number(next(), a); break;
      case '--min-frames': o.minFrames = number(next(), a); break;
      case '--timeout-s': o.timeoutS = number(next(), a); break;
      case '--tolerance': o.tolerance = number(next(), a); break;
      case '--expect-at': {
        const v = next().split(',').map((s) => number(s, a));
        if (v.length !== 3) usage('--expect-at needs X,Y,Z');
        o.expectAt = v;
        break;
      }
      case '--size': {
        const m = /^(\d+)x(\d+)$/.exec(next());
        if (!m) usage('--size needs WxH');
        o.width = Number(m[1]); o.height = Number(m[2]);
        break;
      }
      case '--chromium': o.chromium = next(); break;
      case '--allow-errors': o.allowErrors = true; break;
      case '-h': case '--help': usage(); break;
      default: usage(`unknown argument ${a}`);
    }
  }
  if (!o.url) usage('--url is required');
  if (!o.screenshot) usage('--screenshot is required');
  if (!(o.timeoutS > 0)) usage('--timeout-s must be > 0');
  if (o.expectAt && o.goto === null) usage('--expect-at needs --goto');
  return o;
}

const opts = parseArgs(process.argv.slice(2));

// ---------------------------------------------------------------------------------------------
// The browser and its cleanup.
let chrome = null;                 // the ChildProcess
let chromeExited = false;
let profileDir = null;
let finished = false;
const chromeLog = [];              // the browser's last stderr lines, for a failure message

function killBrowserSync() {
  if (chrome && !chromeExited && chrome.pid) {
    try { process.kill(-chrome.pid, 'SIGKILL'); } catch (e) {      // the whole group: renderers, GPU process
      try { chrome.kill('SIGKILL'); } catch (e2) { /* already gone */ }
    }
  }
  if (profileDir) {
    try { fs.rmSync(profileDir, { recursive: true, force: true }); } catch (e) { /* a late write; retried at exit */ }
  }
}
process.on('exit', killBrowserSync);

function printResult(result) {
  process.stdout.write(JSON.stringify(result) + '\n');
}

// The one way out: print, kill, exit.
function finish(code, result) {
  if (finished) return;
  finished = true;
  printResult(result);
  if (code !== 0) console.error(`check_page: FAILED: ${result.message}`);
  killBrowserSync();
  // Give chromium a moment to die before the profile is removed a second time (exit handler).
  setTimeout(() => process.exit(code), chrome && !chromeExited ? 300 : 0);
}

let partial = { ok: false, url: opts.url };   // what we know so far, for early exits
function fail(message) {
  finish(1, Object.assign({}, partial, { ok: false, message }));
}

for (const sig of ['SIGTERM', 'SIGINT', 'SIGHUP']) process.on(sig, () => fail(`stopped by ${sig}`));
process.on('uncaughtException', (err) => fail(`exception: ${err && err.stack ? err.stack : err}`));
process.on('unhandledRejection', (err) => fail(`exception: ${err && err.stack ? err.stack : err}`));
// Launch and page load get their own time on top of --timeout-s; this is the last resort.
setTimeout(() => fail(`hard timeout after ${opts.timeoutS + 40} s`), (opts.timeoutS + 40) * 1000).unref();

function launchChromium() {
  if (!fs.existsSync(opts.chromium)) throw new Error(`${opts.chromium} not found (apt-get install chromium)`);
  profileDir = fs.mkdtempSync(path.join(os.tmpdir(), 'lpss-check-page-'));
  // The flags of /work/shared/notes/browser.md (headless, WebGL through SwiftShader, no sandbox as
  // root), a DevTools port the browser picks, and no background work that would reach the network
  // or throttle the page's animation frames.
  const args = [
    '--headless=new', '--no-sandbox', '--disable-gpu', '--use-gl=swiftshader', '--enable-unsafe-swiftshader',
    `--window-size=${opts.width},${opts.height}`, '--remote-debugging-port=0', `--user-data-dir=${profileDir}`,
    '--no-first-run', '--no-default-browser-check', '--disable-background-networking', '--disable-component-update',
    '--disable-sync', '--disable-extensions', '--disable-default-apps', '--mute-audio', '--hide-scrollbars',
    '--disable-dev-shm-usage', '--disable-background-timer-throttling', '--disable-renderer-backgrounding',
    '--disable-backgrounding-occluded-windows', 'about:blank',
  ];
  // Its temporary files under the profile too: killed, chromium leaves behind the folder of its singleton
  // socket (org.chromium.Chromium.*), two or three in /tmp at every run of the suite, made in TMPDIR.
  chrome = spawn(opts.chromium, args,
    { detached: true, stdio: ['ignore', 'ignore', 'pipe'], env: { ...process.env, TMPDIR: profileDir } });
  chrome.on('exit', () => { chromeExited = true; });
  return new Promise((resolve, reject) => {
    let buf = '';
    const timer = setTimeout(() => reject(new Error('chromium did not open its DevTools port within 30 s: ' +
      chromeLog.slice(-5).join(' | '))), 30000);
    chrome.on('error', (err) => { clearTimeout(timer); reject(err); });
    chrome.on('exit', (code, sig) => {
      clearTimeout(timer);
      reject(new Error(`chromium exited (${code === null ? sig : code}): ${chromeLog.slice(-5).join(' | ')}`));
    });
    chrome.stderr.setEncoding('utf8');
    chrome.stderr.on('data', (d) => {
      buf += d;
      let nl;
      while ((nl = buf.indexOf('\n')) >= 0) {
        const line = buf.slice(0, nl);
        buf = buf.slice(nl + 1);
        chromeLog.push(line);
        if (chromeLog.length > 50) chromeLog.shift();
        const m = /DevTools listening on (ws:\/\/\S+)/.exec(line);
        if (m) { clearTimeout(timer); resolve(m[1]); }
      }
    });
  });
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
function withTimeout(promise, ms, what) {
  let t;
  return Promise.race([promise, new Promise((_, rej) => { t = setTimeout(() => rej(new Error(`${what}: no answer in ${ms} ms`)), ms); })])
    .finally(() => clearTimeout(t));
}

// What the page holds, read in the page.
function readState() {
  const v = window.lpssView;
  if (!v) return null;
  return { connected: v.connected, frame: v.frame, framesSeen: v.framesSeen, bodies: v.bodies, workers: v.workers,
    origin: v.origin, rates: v.rates || null, errors: v.errors ? v.errors.slice() : [] };
}

async function main() {
  const puppeteer = loadPuppeteer();
  const ws = await launchChromium();
  const browser = await withTimeout(puppeteer.connect({ browserWSEndpoint: ws,
    defaultViewport: { width: opts.width, height: opts.height } }), 20000, 'connect to chromium');
  const pages = await browser.pages();
  const page = pages.length ? pages[0] : await browser.newPage();
  await page.setViewport({ width: opts.width, height: opts.height });

  const consoleErrors = [], pageErrors = [], httpErrors = [], failedRequests = [];
  page.on('console', (m) => { if (m.type() === 'error' && consoleErrors.length < 50) consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => { if (pageErrors.length < 50) pageErrors.push(String(e && e.message ? e.message : e)); });
  page.on('response', (r) => { if (r.status() >= 400 && httpErrors.length < 50) httpErrors.push(`${r.status()} ${r.url()}`); });
  // Which request failed and how (a console error says only the error): reported, not judged (a stream
  // the page drops and opens again fails too).
  page.on('requestfailed', (r) => {
    if (failedRequests.length < 50) failedRequests.push(`${r.url()} (${r.failure() ? r.failure().errorText : '?'})`);
  });
  const errorsNow = (state) => ({ page: pageErrors.slice(), view: state ? state.errors : [], console: consoleErrors.slice(),
    http: httpErrors.slice(), failed: failedRequests.slice() });

  const deadline = Date.now() + opts.timeoutS * 1000;
  await withTimeout(page.goto(opts.url, { waitUntil: 'domcontentloaded', timeout: opts.timeoutS * 1000 }),
    opts.timeoutS * 1000 + 2000, `open ${opts.url}`);

  // 1. The frames (and the bodies) arrive.
  let state = null;
  const reached = (s) => s && s.framesSeen >= opts.minFrames && (opts.expectBodies === null || s.bodies === opts.expectBodies);
  for (;;) {
    state = await withTimeout(page.evaluate(readState), 10000, 'read lpssView');
    partial = Object.assign({ ok: false, url: opts.url }, summary(state), { errors: errorsNow(state) });
    if (reached(state)) break;
    if (Date.now() > deadline) {
      const why = !state ? 'window.lpssView never appeared'
        : `after ${opts.timeoutS} s: ${state.framesSeen} frames seen (want >= ${opts.minFrames}), ${state.bodies} bodies drawn` +
          (opts.expectBodies === null ? '' : ` (want ${opts.expectBodies})`) + (state.connected ? '' : ', not connected');
      return fail(why);
    }
    await sleep(200);
  }

  // 2. Go to a body: it may be named before it is known, so retry until the deadline.
  let gotoResult = null;
  if (opts.goto !== null) {
    const id = /^-?\d+$/.test(opts.goto) ? Number(opts.goto) : opts.goto;
    let ok = false;
    while (!(ok = await page.evaluate((x) => window.lpssView.goTo(x), id))) {
      if (Date.now() > deadline) return fail(`no body ${JSON.stringify(opts.goto)} in the page after ${opts.timeoutS} s`);
      await sleep(200);
    }
    // A few frames and two drawn animation frames after the move.
    const seen0 = (await page.evaluate(readState)).framesSeen;
    const waitUntil = Math.min(deadline, Date.now() + 5000);
    while ((await page.evaluate(readState)).framesSeen < seen0 + 3 && Date.now() < waitUntil) await sleep(100);
    await withTimeout(page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)))),
      5000, 'animation frames').catch(() => {});
    const b = await page.evaluate((x) => window.lpssView.body(x), id);
    gotoResult = { id: opts.goto, found: !!b };
    if (b) {
      const drawnError = Math.max(...b.drawnGlobal.map((v, i) => Math.abs(v - b.global[i])));
      Object.assign(gotoResult, { name: b.name, shape: b.shape, global: b.global, drawnGlobal: b.drawnGlobal, drawnError,
        screen: b.screen, visible: b.visible, worker: b.worker, awake: b.awake, cloned: b.cloned });
      if (opts.expectAt) gotoResult.expectError = Math.max(...b.drawnGlobal.map((v, i) => Math.abs(v - opts.expectAt[i])));
    }
  }

  // 3. The picture and the final state.
  fs.mkdirSync(path.dirname(opts.screenshot), { recursive: true });
  await withTimeout(page.screenshot({ path: opts.screenshot }), 20000, 'screenshot');
  state = await page.evaluate(readState);
  const errors = errorsNow(state);
  const result = Object.assign({ ok: true, message: 'ok', url: opts.url }, summary(state),
    gotoResult ? { goto: gotoResult } : {}, { screenshot: opts.screenshot, errors });
  partial = result;

  const problems = [];
  if (gotoResult) {
    if (!gotoResult.found) problems.push(`body ${opts.goto} vanished after goTo`);
    else {
      if (!gotoResult.visible) problems.push(`body ${opts.goto} not visible after goTo (screen ${gotoResult.screen})`);
      if (!(gotoResult.drawnError <= opts.tolerance)) {
        problems.push(`body ${opts.goto} drawn at ${gotoResult.drawnGlobal}, not at ${gotoResult.global} (error ${gotoResult.drawnError})`);
      }
      if (opts.expectAt && !(gotoResult.expectError <= opts.tolerance)) {
        problems.push(`body ${opts.goto} drawn at ${gotoResult.drawnGlobal}, expected ${opts.expectAt} (error ${gotoResult.expectError})`);
      }
    }
  }
  if (!opts.allowErrors) {
    if (errors.page.length) problems.push(`page errors: ${errors.page.join('; ')}`);
    if (errors.view.length) problems.push(`lpssView.errors: ${errors.view.join('; ')}`);
    if (errors.http.length) problems.push(`HTTP errors: ${errors.http.join('; ')}`);
  }

  // Close politely (the page's connection ends cleanly), then make sure.
  await withTimeout(browser.close(), 5000, 'close chromium').catch(() => {});
  if (problems.length) return finish(1, Object.assign(result, { ok: false, message: problems.join('; ') }));
  return finish(0, result);
}

function summary(s) {
  if (!s) return { connected: false, frame: null, framesSeen: 0, bodies: 0, workers: {}, origin: null };
  return { connected: s.connected, frame: s.frame, framesSeen: s.framesSeen, bodies: s.bodies, workers: s.workers,
    origin: s.origin, rates: s.rates };
}

main().catch((err) => fail(err && err.message ? err.message : String(err)));
