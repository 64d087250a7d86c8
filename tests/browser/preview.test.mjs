// glint preview in a real browser: playwright-core drives Debian's /usr/bin/chromium against
// `glint preview` on a small Cornell box (a glint .json scene, no assets), opened at the address
// it prints (with its token), and checks that other web pages get nothing from it. The page's
// contract is docs/preview.md. Run: GLINT_EXECUTABLE=build/glint node --test tests/browser/preview.test.mjs
// (ctest does this as Browser.PreviewInChromium). Needs `npm ci --prefix tests/browser`, which
// scripts/setup.sh runs.
import {after, before, describe, it} from 'node:test';
import assert from 'node:assert/strict';
import {spawn, execFile} from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import readline from 'node:readline';
import {promisify} from 'node:util';

let chromium;
try {
  ({chromium} = await import('playwright-core'));
} catch (e) {
  throw new Error('tests/browser needs playwright-core: run scripts/setup.sh ' +
                  `(or npm ci --prefix tests/browser) (${e.message})`);
}

const glint = process.env.GLINT_EXECUTABLE;
const chromiumPath = process.env.GLINT_CHROMIUM ?? '/usr/bin/chromium';
const runFile = promisify(execFile);
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

// The Cornell box of tests/test_support.cpp (cornellBoxJson), 96×72 with the path integrator.
// `left` is the colour of the left wall, `radius` the sphere's.
function sceneJson({left = [0.7, 0.12, 0.1], radius = 0.35} = {}) {
  return JSON.stringify({
    render: {width: 96, height: 72, spp: 64, seed: 7, camera: 'c', integrator: 'path'},
    cameras: [{name: 'c', position: [0, 1, 0.95], look_at: [0, 1, -1], yfov_degrees: 70}],
    lights: [{type: 'quad', corner: [-0.3, 1.99, -0.3], edge_u: [0.6, 0, 0], edge_v: [0, 0, 0.6],
              intensity: 10}],
    materials: [{name: 'white', type: 'lambert', diffuse: [0.7, 0.7, 0.7]},
                {name: 'left', type: 'lambert', diffuse: left},
                {name: 'green', type: 'lambert', diffuse: [0.12, 0.6, 0.15]}],
    objects: [
      {type: 'quad', corner: [-1, 0, -1], edge_u: [2, 0, 0], edge_v: [0, 0, 2], material: 'white'},
      {type: 'quad', corner: [-1, 2, -1], edge_u: [2, 0, 0], edge_v: [0, 0, 2], material: 'white'},
      {type: 'quad', corner: [-1, 0, -1], edge_u: [2, 0, 0], edge_v: [0, 2, 0], material: 'white'},
      {type: 'quad', corner: [-1, 0, 1], edge_u: [2, 0, 0], edge_v: [0, 2, 0], material: 'white'},
      {type: 'quad', corner: [-1, 0, -1], edge_u: [0, 0, 2], edge_v: [0, 2, 0], material: 'left'},
      {type: 'quad', corner: [1, 0, -1], edge_u: [0, 0, 2], edge_v: [0, 2, 0], material: 'green'},
      {type: 'box', min: [-0.6, 0, -0.6], max: [-0.1, 0.9, -0.1], material: 'white'},
      {type: 'sphere', center: [0.45, 0.35, -0.3], radius, material: 'white'}],
  }, null, 2);
}

// Replaces the file in one step, as editors do, so the watcher never sees half a file.
function writeAtomically(file, text) {
  fs.writeFileSync(`${file}.tmp`, text);
  fs.renameSync(`${file}.tmp`, file);
}

// Mean R, G, B (0..255) of the image the page shows, read back through a canvas.
function meanRgbInPage() {
  const img = document.getElementById('image');
  if (!img.complete || !img.naturalWidth) return null;
  const canvas = document.createElement('canvas');
  canvas.width = img.naturalWidth;
  canvas.height = img.naturalHeight;
  const context = canvas.getContext('2d');
  context.drawImage(img, 0, 0);
  const data = context.getImageData(0, 0, canvas.width, canvas.height).data;
  const sum = [0, 0, 0];
  for (let i = 0; i < data.length; i += 4) for (let c = 0; c < 3; c++) sum[c] += data[i + c];
  return sum.map((s) => s / (data.length / 4));
}

const distance = (a, b) => Math.hypot(...a.map((x, i) => x - b[i]));

describe('glint preview in Chromium', {timeout: 240_000}, () => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'glint-preview-test-'));
  const scene = path.join(dir, 'box.json');
  let server, serverLog = '', url, token, browser, page;
  const cameraPosts = [];
  let failed = false;

  async function state() {
    const response = await fetch(new URL('api/state', url), {headers: {'X-Glint-Token': token}});
    assert.equal(response.status, 200);
    return response.json();
  }

  // Polls `condition` every 100 ms until it holds.
  async function waitFor(condition, what, timeout = 20_000) {
    const end = Date.now() + timeout;
    while (Date.now() < end) {
      const result = await condition();
      if (result) return result;
      await sleep(100);
    }
    assert.fail(`timed out waiting for ${typeof what === 'function' ? what() : what}`);
  }

  // Polls the server's state until `predicate` holds.
  async function waitForState(predicate, what, timeout = 20_000) {
    let last;
    await waitFor(async () => predicate(last = await state()),
                  () => `${what}; last state: ${JSON.stringify(last)}`, timeout);
    return last;
  }

  const mean = () => page.evaluate(meanRgbInPage);
  const version = async () => Number(await page.evaluate(() => document.body.dataset.version));

  before(async () => {
    assert.ok(glint, 'set GLINT_EXECUTABLE to the glint executable');
    writeAtomically(scene, sceneJson());
    server = spawn(glint, ['preview', scene, '--port', '0', '--spp', '64', '--output-dir', dir],
                   {cwd: dir, stdio: ['ignore', 'pipe', 'pipe']});
    server.stderr.on('data', (d) => { serverLog += d; });
    const lines = readline.createInterface({input: server.stdout});
    url = await new Promise((resolve, reject) => {
      const timer = setTimeout(() => reject(new Error(`no URL from glint preview in 20 s:\n${serverLog}`)),
                               20_000);
      server.once('exit', (code, signal) =>
        reject(new Error(`glint preview exited (${code ?? signal}) before its URL:\n${serverLog}`)));
      server.once('error', reject);
      lines.once('line', (line) => {
        clearTimeout(timer);
        const match = /^glint: preview at (http:\/\/127\.0\.0\.1:\d+\/\?token=([0-9a-f]{64}))$/.exec(line);
        if (match) {
          token = match[2];
          resolve(match[1]);
        } else reject(new Error(`first stdout line is not the URL: ${JSON.stringify(line)}`));
      });
    });
    lines.on('line', (line) => { serverLog += `${line}\n`; });

    // evil.example stands for another site, and for DNS rebinding: a name of its own that
    // resolves to 127.0.0.1.
    browser = await chromium.launch({executablePath: chromiumPath, headless: true,
                                     args: ['--no-sandbox', '--host-resolver-rules=MAP evil.example 127.0.0.1']});
    page = await browser.newPage({viewport: {width: 1100, height: 800}});
    page.setDefaultTimeout(20_000);
    page.on('pageerror', (e) => { serverLog += `page error: ${e}\n`; });
    page.on('request', (request) => {
      if (request.method() === 'POST' && new URL(request.url()).pathname === '/api/camera')
        cameraPosts.push({at: Date.now(), body: JSON.parse(request.postData())});
    });
    await page.goto(url);
  });

  after(async () => {
    await browser?.close();
    if (server && server.exitCode === null && server.signalCode === null) {
      const exited = new Promise((resolve) => server.once('exit', resolve));
      server.kill('SIGINT');
      const timer = setTimeout(() => server.kill('SIGKILL'), 5000);
      await exited;
      clearTimeout(timer);
    }
    if (failed) console.log(`kept ${dir}; glint preview said:\n${serverLog}`);
    else fs.rmSync(dir, {recursive: true, force: true});
  });

  // A failing step marks the run so that `after` keeps the folder and prints the server's log.
  const step = (name, body) => it(name, async () => {
    try { await body(); } catch (e) { failed = true; throw e; }
  });

  step('shows the image refining, with spp, error and time', async () => {
    await page.waitForFunction(() => Number(document.getElementById('spp').textContent) >= 8);
    await page.waitForFunction(() => document.body.dataset.imageVersion);
    const rgb = await mean();
    assert.ok(rgb && rgb[0] + rgb[1] + rgb[2] > 15, `image nearly black: mean ${rgb}`);
    assert.match(await page.textContent('#error'), /^\d+(\.\d+)? %$/);
    assert.match(await page.textContent('#seconds'), /^\d+(\.\d+)? s$/);
    assert.ok(await page.isHidden('#problem'));
    const s = await state();
    assert.equal(s.scene, 'box.json');
    assert.deepEqual([s.width, s.height], [96, 72]);
    assert.deepEqual(await page.$$eval('#aov option', (o) => o.map((x) => x.value)), s.aovs);
  });

  step('other web pages get nothing: no token, another Host, a change from another origin', async () => {
    const {origin, port} = new URL(url);  // http://127.0.0.1:PORT
    const other = await browser.newPage();
    other.setDefaultTimeout(20_000);
    // A page of another site, served on another port of evil.example.
    const site = http.createServer((request, response) => {
      response.writeHead(200, {'Content-Type': 'text/html'});
      response.end('<!DOCTYPE html><title>another site</title>');
    });
    await new Promise((resolve) => site.listen(0, '127.0.0.1', resolve));
    try {
      // The page without its token.
      let response = await other.goto(`${origin}/`);
      assert.equal(response.status(), 403);
      assert.match(await response.text(), /token/);
      // DNS rebinding: a name that resolves to 127.0.0.1 (the token known, even) gets nothing.
      response = await other.goto(`http://evil.example:${port}/?token=${token}`);
      assert.equal(response.status(), 403);
      assert.match(await response.text(), /Host/);
      // Another site's page posts a camera: a "simple" request, sent without a preflight,
      // the token known even. The browser says where it comes from; the server refuses it.
      const s0 = await state();
      await other.goto(`http://evil.example:${site.address().port}/`);
      const [answer] = await Promise.all([
        other.waitForResponse((r) => new URL(r.url()).pathname === '/api/camera'),
        other.evaluate(([target, body]) => fetch(target, {method: 'POST', mode: 'no-cors', body})
          .then(() => 'sent', (e) => `${e}`),
        [`${origin}/api/camera?token=${token}`, JSON.stringify({position: [0, 1.5, 0.9], look_at: [0, 0.5, -1]})]),
      ]);
      assert.equal(answer.status(), 403);
      await sleep(300);
      const s1 = await state();
      assert.equal(s1.custom_camera, false);
      assert.equal(s1.generation, s0.generation);
    } finally {
      await other.close();
      site.close();
    }
    assert.ok(await page.isHidden('#connection'), 'the preview\'s own page lost its server');
  });

  let blue;
  step('an edit of the scene re-renders: the left wall turns blue', async () => {
    const before = await mean();
    const v0 = await version();
    writeAtomically(scene, sceneJson({left: [0.05, 0.1, 0.9]}));
    await waitFor(async () => {
      if (!(Number(await page.evaluate(() => document.body.dataset.imageVersion)) > v0)) return false;
      blue = await mean();
      return blue && blue[2] > before[2] + 8 && blue[0] < before[0] - 4;
    }, () => `a bluer image; mean was ${before}, is ${blue}`);
    assert.ok(await version() > v0);
  });

  step('a bad edit shows the error with file and JSON pointer, keeping the image', async () => {
    writeAtomically(scene, sceneJson({left: [0.05, 0.1, 0.9], radius: -1}));
    await page.waitForSelector('#problem', {state: 'visible'});
    const problem = await page.textContent('#problem');
    assert.match(problem, /box\.json/);
    assert.match(problem, /\/objects\/7\/radius/);
    assert.ok((await state()).problem.includes('/objects/7/radius'));
    const rgb = await mean();
    assert.ok(rgb && rgb[2] > blue[2] - 8, `the last good image is gone: mean ${rgb}, was ${blue}`);
  });

  step('fixing it clears the error', async () => {
    writeAtomically(scene, sceneJson({left: [0.05, 0.1, 0.9]}));
    await page.waitForSelector('#problem', {state: 'hidden'});
    assert.equal(await page.textContent('#problem'), '');
  });

  step('Save EXR at 64 spp equals glint render at 64 spp', async () => {
    await waitForState((s) => !s.rendering && s.spp === 64 && s.problem === null, 'spp 64, done');
    await page.waitForFunction(() => document.getElementById('spp').textContent === '64');
    const [response] = await Promise.all([
      page.waitForResponse((r) => new URL(r.url()).pathname === '/api/save'),
      page.click('#save-exr'),
    ]);
    assert.equal(response.status(), 200);
    assert.equal((await response.json()).spp, 64);
    await page.waitForFunction(() => document.getElementById('saved-path').textContent !== '');
    const saved = await page.textContent('#saved-path');
    assert.equal(path.basename(saved), 'box_preview.exr');
    assert.ok(fs.existsSync(saved), `${saved} missing`);

    const reference = path.join(dir, 'ref.exr');
    await runFile(glint, ['render', scene, '--spp', '64', '-o', reference, '--quiet']);
    // glint diff compares the channels both have by name: R, G, B and A. The same passes of the
    // same scene and seed give the same pixels whatever the threads, so nothing may differ.
    const {stdout} = await runFile(glint, ['diff', saved, reference, '--fail', '0', '--json'])
      .catch((e) => assert.fail(`glint diff ${saved} ${reference} failed (${e.code}):\n${e.stdout}${e.stderr}`));
    const diff = JSON.parse(stdout);
    assert.deepEqual(diff.channels, ['R', 'G', 'B', 'A']);
    assert.equal(diff.max_error, 0);
  });

  step('Save PNG writes the PNG', async () => {
    await page.click('#save-png');
    await page.waitForFunction(() => document.getElementById('saved-path').textContent.endsWith('.png'));
    const saved = await page.textContent('#saved-path');
    assert.equal(path.basename(saved), 'box_preview.png');
    assert.deepEqual([...fs.readFileSync(saved).subarray(0, 4)], [0x89, 0x50, 0x4e, 0x47]);
  });

  step('every AOV, view and tone mapping displays; exposure brightens', async () => {
    const shown = (query) => page.waitForFunction(
      (q) => document.body.dataset.imageQuery === q, query);
    const query = () => page.evaluate(() => document.body.dataset.imageQuery);
    const s = await state();
    for (const aov of s.aovs) {
      await page.selectOption('#aov', aov);
      await page.waitForFunction((a) => document.body.dataset.imageQuery.startsWith(`aov=${a}&`), aov);
      assert.ok(await page.isHidden('#message'), `aov ${aov}: ${await page.textContent('#message')}`);
    }
    await page.selectOption('#aov', 'beauty');
    assert.ok(s.views.length > 0 && s.views.includes(s.default_view), `views ${s.views}`);
    assert.equal(await page.inputValue('#view'), s.default_view);
    for (const view of s.views) {
      await page.selectOption('#view', view);
      await page.waitForFunction((v) => new URLSearchParams(document.body.dataset.imageQuery).get('view') === v, view);
      assert.ok(await page.isHidden('#message'), `view ${view}: ${await page.textContent('#message')}`);
    }
    await page.selectOption('#view', s.default_view);
    await page.selectOption('#tonemap', 'ward');
    await page.waitForFunction(() => document.body.dataset.imageQuery.includes('tonemap=ward'));
    assert.ok(await page.isHidden('#message'), await page.textContent('#message'));
    await page.selectOption('#tonemap', 'none');
    await page.waitForFunction(() => document.body.dataset.imageQuery.includes('tonemap=none'));
    const dark = await mean();
    await page.fill('#exposure', '2');
    await page.waitForFunction(() => document.body.dataset.imageQuery.includes('exposure=2&'));
    const bright = await mean();
    assert.ok(bright[1] > dark[1] + 10, `+2 EV: mean ${bright}, at 0 EV ${dark}`);
    await page.fill('#exposure', '0');
    await shown((await query()).replace('exposure=2&', 'exposure=0&'));
  });

  step('dragging orbits the camera about the bounds, wheel dollies, Camera JSON shows it', async () => {
    const s0 = await state();
    const centre = s0.bounds.min.map((x, i) => (x + s0.bounds.max[i]) / 2);
    const radius = distance(s0.camera.position, centre);
    const box = await page.locator('#image').boundingBox();
    const x = box.x + box.width / 2, y = box.y + box.height / 2;
    const start = Date.now();
    await page.mouse.move(x, y);
    await page.mouse.down();
    for (let i = 1; i <= 20; i++) {
      await page.mouse.move(x + 4 * i, y + i);
      await sleep(30);
    }
    await page.mouse.up();
    // Waited for rather than slept on: on a loaded machine (CI runs tests two at a time) the
    // page's throttled POST can take longer than any fixed pause.
    await waitFor(() => cameraPosts.length >= 1, 'a POST /api/camera after the drag');
    await sleep(300);  // the throttle's last POST, if one is pending
    const seconds = (Date.now() - start) / 1000;
    assert.ok(cameraPosts.length <= 5 * seconds + 2,
              `${cameraPosts.length} camera POSTs in ${seconds} s: not throttled`);
    const last = cameraPosts.at(-1).body;
    assert.ok(Math.abs(distance(last.position, centre) - radius) < 1e-6 * Math.max(1, radius),
              `orbit changed the distance to the centre: ${JSON.stringify(last)}`);
    assert.ok(distance(last.look_at, centre) < 1e-9);
    assert.ok(distance(last.position, s0.camera.position) > 0.05, 'the drag did not move the camera');
    assert.deepEqual(last.up, s0.camera.up);
    const s1 = await waitForState((s) => s.custom_camera && distance(s.camera.position, last.position) < 1e-6,
                                  'the dragged camera');
    assert.ok(s1.generation > s0.generation);

    const posts = cameraPosts.length;
    await page.mouse.move(x, y);
    await page.mouse.wheel(0, 300);
    await waitFor(() => cameraPosts.length > posts, 'a POST /api/camera after the wheel');
    assert.ok(distance(cameraPosts.at(-1).body.position, centre) > radius * 1.05, 'wheel down did not dolly out');

    await page.click('#camera-json');
    await page.waitForFunction(() => document.getElementById('camera-json-text').textContent.includes('"cameras"'));
    const block = JSON.parse(await page.textContent('#camera-json-text'));
    assert.equal(block.cameras[0].name, 'preview');
    assert.equal(block.render.camera, 'preview');
  });

  step('Scene camera goes back to the scene\'s own', async () => {
    await page.click('#scene-camera');
    const s = await waitForState((s) => !s.custom_camera, 'custom_camera false');
    assert.ok(distance(s.camera.position, [0, 1, 0.95]) < 1e-6);
    // The page shows a pass from it. (The camera the wheel dollied out sits outside the closed
    // box, whose outside is unlit: its image is black, and a page stopped before the first pass
    // from inside arrived would keep that one, which the next step would take for a lost image.)
    const pass = await waitForState((s) => !s.custom_camera && s.spp >= 1, 'a pass from the scene camera');
    await page.waitForFunction((v) => Number(document.body.dataset.imageVersion) >= v, pass.version);
  });

  step('when the server goes away the page says so and keeps the image', async () => {
    const exited = new Promise((resolve) => server.once('exit', (code, signal) => resolve(code ?? signal)));
    const start = Date.now();
    server.kill('SIGINT');
    const code = await exited;
    // Not asserted: how long Ctrl-C takes while the page holds a long poll (up to its 10 s).
    console.log(`glint preview stopped ${Date.now() - start} ms after SIGINT (exit ${code})`);
    assert.equal(code, 0);
    await page.waitForSelector('#connection', {state: 'visible', timeout: 15_000});
    // The image may be mid-swap to the server's last version (then it is not yet `complete`);
    // it must settle to a visible image, not a broken one.
    let rgb;
    await waitFor(async () => (rgb = await mean()) !== null,
                  'the image to be shown (a broken image never is)', 5_000);
    const shownImage = await page.evaluate(() => {
      const img = document.getElementById('image');
      return `version ${document.body.dataset.imageVersion}, query ${document.body.dataset.imageQuery}, ` +
             `${img.naturalWidth}x${img.naturalHeight}, src ${img.src}`;
    });
    assert.ok(rgb[0] + rgb[1] + rgb[2] > 15,
              `the image went away with the server: mean ${rgb} (${shownImage})`);
  });

  step('a preview started again on the port refuses the old page\'s token, and the page says so', async () => {
    server = spawn(glint, ['preview', scene, '--port', new URL(url).port, '--spp', '4', '--output-dir', dir],
                   {cwd: dir, stdio: ['ignore', 'pipe', 'pipe']});
    server.stderr.on('data', (d) => { serverLog += d; });
    await page.waitForFunction(
      () => document.getElementById('connection').textContent.includes('wrong token'));
    assert.ok(await page.isVisible('#connection'));
    assert.match(await page.textContent('#connection'), /^glint preview refused: wrong token/);
  });
});
