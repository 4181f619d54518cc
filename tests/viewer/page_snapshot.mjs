// Opens a semfuse-viewer page in headless Chromium over the DevTools protocol, waits until it
// shows a mesh of at least --blocks blocks and a frame counter of at least --frames, then saves a
// screenshot and what the page shows (counters, legend, where given world points land on screen)
// as "key value" lines for viewer_page_test.cpp. Needs Node's WebSocket (--experimental-websocket).
//   node --experimental-websocket page_snapshot.mjs --chromium PATH --url URL --png OUT.png
//        --facts OUT.txt --blocks N --frames N [--timeout-s S] [--ready FILE] [--point NAME X Y Z]...
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

const args = { points: [], timeout_s: 120 };
const argv = process.argv.slice(2);
for (let i = 0; i < argv.length; ++i) {
  const key = argv[i].replace(/^--/, '').replace(/-/g, '_');
  if (key === 'point') { args.points.push(argv.slice(i + 1, i + 5)); i += 4; } else args[key] = argv[++i];
}

const started = Date.now();
const log = (what) => console.error(`page_snapshot: ${((Date.now() - started) / 1000).toFixed(1)} s: ${what}`);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// The viewer may still be starting: wait until it answers.
for (;;) {
  try { if ((await fetch(new URL('/api/status', args.url))).ok) break; } catch { /* not yet */ }
  if (Date.now() - started > args.timeout_s * 1000) { console.error('page_snapshot: no viewer at ' + args.url); process.exit(1); }
  await sleep(200);
}
log('viewer answers');

const profile = mkdtempSync(join(tmpdir(), 'semfuse-chromium-'));
const browser = spawn(args.chromium, [
  '--headless=new', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--remote-debugging-port=0', `--user-data-dir=${profile}`, '--window-size=1200,800',
  '--force-device-scale-factor=1', '--hide-scrollbars', 'about:blank'], { stdio: ['ignore', 'ignore', 'pipe'] });
const fail = (why) => { console.error(`page_snapshot: ${why}`); browser.kill('SIGKILL'); rmSync(profile, { recursive: true, force: true }); process.exit(1); };
setTimeout(() => fail(`timed out after ${args.timeout_s} s`), args.timeout_s * 1000).unref();

const devtools = await new Promise((resolve) => {
  let text = '';
  browser.stderr.on('data', (chunk) => {
    text += chunk;
    const m = text.match(/DevTools listening on (ws:\/\/[^\s]+)/);
    if (m) resolve(new URL(m[1]));
  });
  browser.once('exit', onExit);
  function onExit(code) { fail(`chromium exited (${code}): ${text.slice(-500)}`); }
  browser.onExit = onExit;
});
const targets = await (await fetch(`http://${devtools.host}/json/list`)).json();
const page = targets.find((t) => t.type === 'page');
if (!page) fail('no page target');

const socket = new WebSocket(page.webSocketDebuggerUrl);
await new Promise((resolve, reject) => { socket.onopen = resolve; socket.onerror = reject; });
let nextId = 1;
const pending = new Map();
socket.onmessage = (e) => {
  const m = JSON.parse(e.data);
  if (m.id && pending.has(m.id)) { pending.get(m.id)(m); pending.delete(m.id); }
};
const call = (method, params = {}) => new Promise((resolve) => {
  const id = nextId++;
  pending.set(id, resolve);
  socket.send(JSON.stringify({ id, method, params }));
});
const evaluate = async (expression) => {
  const r = await call('Runtime.evaluate', { expression, returnByValue: true });
  return r.result && r.result.result ? r.result.result.value : undefined;
};

await call('Page.enable');
await call('Page.navigate', { url: args.url });

// What the page shows now.
const facts = () => evaluate(`(() => {
  const text = (id) => { const e = document.getElementById(id); return e ? e.textContent.replace(/,/g, '') : ''; };
  return {
    blocks: Number(document.body.dataset.blocks || 0),
    poses: Number(document.body.dataset.poses || 0),
    frames: Number(text('frames-integrated')) || 0,
    connection: text('connection'),
    legend: [...document.querySelectorAll('#legend tr')].map((r) => [...r.cells].map((c) => c.textContent.trim()).join(' ')),
  };
})()`);

// With --ready FILE: the file is written once the page's websocket is connected, so that the
// test can start the camera then and the page sees the map grow from its first frames.
if (args.ready) {
  while ((await facts())?.connection !== 'connected') await sleep(100);
  writeFileSync(args.ready, 'connected\n');
  log('page connected');
}

const framesSeen = [];
let last;
for (;;) {
  last = await facts();
  if (last && last.frames && framesSeen[framesSeen.length - 1] !== last.frames) {
    framesSeen.push(last.frames);
    log(`frames ${last.frames}, blocks ${last.blocks}`);
  }
  if (last && last.blocks >= Number(args.blocks) && last.frames >= Number(args.frames)) break;
  await sleep(200);
}
await sleep(1500);  // the last blocks drawn, the view fitted
last = await facts();

const shot = await call('Page.captureScreenshot', { format: 'png' });
writeFileSync(args.png, Buffer.from(shot.result.data, 'base64'));

const lines = [
  `blocks ${last.blocks}`, `poses ${last.poses}`, `frames ${last.frames}`,
  `frames_seen ${framesSeen.join(' ')}`,
  ...last.legend.map((row) => `legend ${row}`),
];
for (const [name, x, y, z] of args.points) {
  const p = await evaluate(`window.semfuseProject(${x}, ${y}, ${z})`);
  lines.push(`point ${name} ${p[0]} ${p[1]}`);
}
// A click on the first point: the page asks labels_at there and shows the answer.
if (args.points.length > 0) {
  const [, x, y, z] = args.points[0];
  const [px, py] = await evaluate(`window.semfuseProject(${x}, ${y}, ${z})`);
  for (const type of ['mousePressed', 'mouseReleased'])
    await call('Input.dispatchMouseEvent', { type, x: px, y: py, button: 'left', clickCount: 1 });
  let probe = '';
  for (let i = 0; i < 50 && !/^label /m.test(probe); ++i) {
    await sleep(200);
    probe = await evaluate(`document.getElementById('probe').textContent`);
  }
  for (const row of probe.split('\n')) lines.push(`probe ${row}`);
  // The raycast from the clicked view: its size, and how many of its pixels have each colour.
  let raycast = null;
  for (let i = 0; i < 50 && !raycast; ++i) {
    await sleep(200);
    raycast = await evaluate(`(() => {
      const img = document.getElementById('raycast');
      if (!img.complete || !img.naturalWidth) return null;
      const c = document.createElement('canvas');
      c.width = img.naturalWidth; c.height = img.naturalHeight;
      const g = c.getContext('2d');
      g.drawImage(img, 0, 0);
      const d = g.getImageData(0, 0, c.width, c.height).data;
      const counts = {};
      for (let i = 0; i < d.length; i += 4) { const k = d[i] + ',' + d[i + 1] + ',' + d[i + 2]; counts[k] = (counts[k] || 0) + 1; }
      return { w: c.width, h: c.height, counts };
    })()`);
  }
  if (raycast) {
    lines.push(`raycast_size ${raycast.w} ${raycast.h}`);
    for (const [rgb, n] of Object.entries(raycast.counts)) lines.push(`raycast_color ${rgb.replace(/,/g, ' ')} ${n}`);
  }
}
writeFileSync(args.facts, lines.join('\n') + '\n');
socket.close();
browser.removeListener('exit', browser.onExit);
browser.kill('SIGTERM');
await sleep(300);
rmSync(profile, { recursive: true, force: true });
process.exit(0);
