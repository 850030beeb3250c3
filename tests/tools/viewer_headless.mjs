// Drives sweepd's browser viewer in Debian's headless Chromium (WebGL on SwiftShader, no GPU)
// over the DevTools protocol on a pipe (--remote-debugging-pipe: commands on fd 3, events and
// answers on fd 4, each JSON message ended by a NUL byte). Used by
// tests/server/browser_viewer_test.cpp and bench/viewer_bench.sh.
//
//   node tests/tools/viewer_headless.mjs --url URL [--bvh FILE | --turn JOINT:X,Y,Z | --stream]
//        [--frames N] [--seconds S] [--screenshot OUT.png] [--status OUT.json]
//        [--width 1200] [--height 700]
//
// Loads URL (the viewer, /viewer?ws=...&token=...) and waits for the rest pose ("ready"). With
// --bvh it gives the page's clip input the BVH FILE (the page uploads it and streams it) and
// waits until N pose sets are drawn and S seconds have passed while streaming; with --turn it
// picks JOINT in the page and moves its sliders to X, Y, Z degrees in N steps, each step's pose
// drawn; with --stream (the URL says stream=NAME) it waits until N of the stream's frames are
// drawn (someone else sends them) and S seconds have passed. Writes the page's status (#status's data attributes: state, error, figures, viewports)
// as JSON and a screenshot. Exit 0 when the page did so without error; 1 with the reason.
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { parseArgs } from 'node:util';

const { values: options } = parseArgs({
  options: {
    url: { type: 'string' },
    bvh: { type: 'string' },
    turn: { type: 'string' },
    stream: { type: 'boolean', default: false },
    frames: { type: 'string', default: '30' },
    seconds: { type: 'string', default: '0' },
    screenshot: { type: 'string' },
    status: { type: 'string' },
    width: { type: 'string', default: '1200' },
    height: { type: 'string', default: '700' },
    chromium: { type: 'string', default: 'chromium' },
    timeout: { type: 'string', default: '120' },
  },
});
if (!options.url) throw new Error('--url is required');

const profile = mkdtempSync(join(tmpdir(), 'viewer-chromium-'));
const browser = spawn(options.chromium, [
  '--headless', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--remote-debugging-pipe', `--user-data-dir=${profile}`,
  `--window-size=${options.width},${options.height}`,
  // Containers often have a small /dev/shm: shared memory goes to /tmp instead.
  '--hide-scrollbars', '--no-first-run', '--no-default-browser-check', '--disable-dev-shm-usage',
  'about:blank',
], { stdio: ['ignore', 'ignore', 'pipe', 'pipe', 'pipe'] });
let browserLog = '';
browser.stderr.on('data', (chunk) => { browserLog = (browserLog + chunk).slice(-4000); });

// The DevTools protocol: send(method, params, sessionId) resolves with the result.
let nextId = 1;
const answers = new Map();
let received = '';
browser.stdio[4].on('data', (chunk) => {
  received += chunk.toString('utf8');
  for (let end = received.indexOf('\0'); end >= 0; end = received.indexOf('\0')) {
    const message = JSON.parse(received.slice(0, end));
    received = received.slice(end + 1);
    const answer = answers.get(message.id);
    if (!answer) continue;
    answers.delete(message.id);
    if (message.error) answer.reject(new Error(`${answer.method}: ${message.error.message}`));
    else answer.resolve(message.result);
  }
});
function send(method, params = {}, sessionId = undefined) {
  const id = nextId++;
  browser.stdio[3].write(JSON.stringify({ id, method, params, sessionId }) + '\0');
  return new Promise((resolve, reject) => answers.set(id, { resolve, reject, method }));
}

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
const deadline = Date.now() + Number(options.timeout) * 1000;

async function pageStatus(session) {
  const { result } = await send('Runtime.evaluate', {
    expression: `JSON.stringify(Object.assign({}, document.getElementById('status')?.dataset))`,
    returnByValue: true,
  }, session);
  const status = JSON.parse(result.value ?? '{}');
  for (const key of ['figures', 'viewports']) status[key] = JSON.parse(status[key] ?? 'null');
  return status;
}

// Polls until `done(status)`; throws on the page's error state or the deadline.
async function waitFor(session, what, done) {
  for (;;) {
    const status = await pageStatus(session);
    const failure = status.state === 'error' ? `page error: ${status.error}`
                  : Date.now() > deadline ? `timed out waiting for ${what}` : null;
    if (done(status)) return status;
    if (failure) throw Object.assign(new Error(failure), { status });
    await sleep(100);
  }
}

// Moves JOINT's sliders to X, Y, Z degrees in --frames steps, as a person would: each step's
// pose (PoseByName) is drawn before the next.
async function turnJoint(session, turn) {
  const [joint, angles] = turn.split(':');
  const target = angles.split(',').map(Number);
  const steps = Number(options.frames);
  let status = await pageStatus(session);
  for (let step = 1; step <= steps; ++step) {
    const drawn = status.figures?.frames ?? 0;
    const degrees = target.map((angle) => (angle * step) / steps);
    await send('Runtime.evaluate', { expression: `{
      const select = document.getElementById('joint');
      select.value = ${JSON.stringify(joint)};
      select.dispatchEvent(new Event('change'));
      ${JSON.stringify(degrees)}.forEach((value, axis) => {
        const slider = document.getElementById('joint-' + 'xyz'[axis]);
        slider.value = value;
        slider.dispatchEvent(new Event('input'));
      });
    }` }, session);
    status = await waitFor(session, `the joint turned, step ${step}`,
                           (s) => s.state === 'posing' && s.figures?.frames > drawn);
  }
  return status;
}

async function run() {
  const { targetInfos } = await send('Target.getTargets');
  const page = targetInfos.find((target) => target.type === 'page');
  const { sessionId } =
      await send('Target.attachToTarget', { targetId: page.targetId, flatten: true });
  await send('Page.enable', {}, sessionId);
  await send('Page.navigate', { url: options.url }, sessionId);
  if (options.stream) {
    // Frames drawn are the stream's: the rest pose is not counted.
    const since = Date.now();
    const wanted = `${options.frames} of the stream's frames drawn`;
    const streamed = await waitFor(sessionId, wanted, (s) =>
      s.state === 'streaming' && (s.figures?.frames ?? 0) >= Number(options.frames) &&
      Date.now() - since >= Number(options.seconds) * 1000);
    return finish(sessionId, streamed);
  }
  // Ready, and the rest pose drawn: the page says 'ready' before its first reply arrives, and
  // --turn counts each step's frame after the rest pose's.
  let status = await waitFor(sessionId, 'the rest pose',
                             (s) => s.state === 'ready' && (s.figures?.frames ?? 0) >= 1);
  if (options.bvh) {
    const { root } = await send('DOM.getDocument', {}, sessionId);
    const { nodeId } = await send('DOM.querySelector',
                                  { nodeId: root.nodeId, selector: '#clip-file' }, sessionId);
    await send('DOM.setFileInputFiles', { nodeId, files: [resolve(options.bvh)] }, sessionId);
    await waitFor(sessionId, 'streaming', (s) => s.state === 'streaming');
    const streamingSince = Date.now();
    status = await waitFor(sessionId, `${options.frames} frames drawn`, (s) =>
      (s.figures?.frames ?? 0) >= Number(options.frames) &&
      Date.now() - streamingSince >= Number(options.seconds) * 1000);
  }
  if (options.turn) status = await turnJoint(sessionId, options.turn);
  return finish(sessionId, status);
}

async function finish(sessionId, status) {
  if (options.screenshot) {
    const { data } = await send('Page.captureScreenshot', { format: 'png' }, sessionId);
    writeFileSync(options.screenshot, Buffer.from(data, 'base64'));
  }
  return status;
}

let exitCode = 0;
let status = {};
try {
  status = await run();
} catch (error) {
  status = { ...(error.status ?? {}), driver_error: error.message };
  console.error(`viewer_headless: ${error.message}\nchromium's last output:\n${browserLog}`);
  exitCode = 1;
}
if (options.status) writeFileSync(options.status, JSON.stringify(status, null, 2) + '\n');
console.log(JSON.stringify(status));
send('Browser.close').catch(() => {});
await Promise.race([new Promise((resolve) => browser.on('exit', resolve)), sleep(5000)]);
browser.kill('SIGKILL');
rmSync(profile, { recursive: true, force: true });
process.exit(exitCode);
