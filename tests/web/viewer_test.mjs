// The web viewer (client/web) in real headless Chromium (Debian's, driven by puppeteer-core)
// against the real tessera-server on loopback: a mesh the server lacks is named as missing (not
// "no meshes yet"), the page loads without console errors, the GLB renders (a screenshot whose
// silhouette covers a plausible share of the view), and in server-frame mode a new frame from the
// server arrives after the camera moves.
// Usage: node viewer_test.mjs SERVER_BINARY SAMPLE_OBJ WORK_DIR
import { spawn } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import puppeteer from 'puppeteer-core';

const [server, sample, work] = process.argv.slice(2);
const chromium = process.env.CHROMIUM || '/usr/bin/chromium';
const fail = (message) => { throw new Error(message); };

function startServer() {
  rmSync(work, { recursive: true, force: true });
  mkdirSync(work, { recursive: true });
  const ready = path.join(work, 'ready');
  const child = spawn(server, ['--listen', '127.0.0.1:0', '--metrics-listen', 'off', '--http-listen', '127.0.0.1:0',
                               '--store', `sqlite:${path.join(work, 'viewer.db')}`, '--ready-file', ready],
                      { stdio: ['ignore', 'inherit', 'inherit'] });
  return new Promise((resolve, reject) => {
    const deadline = Date.now() + 30000;
    const poll = () => {
      if (existsSync(ready)) {
        const http = readFileSync(ready, 'utf8').match(/^http=(.*)$/m);
        return http ? resolve({ child, base: `http://${http[1]}` }) : reject(new Error('no http= in the ready file'));
      }
      if (Date.now() > deadline) return reject(new Error('the server did not start'));
      setTimeout(poll, 100);
    };
    poll();
  });
}

// The share of the screenshot's pixels that differ from the viewer's background (0x20242a).
async function coverage(page, keepAs) {
  const png = await page.screenshot({ encoding: 'base64' });
  writeFileSync(keepAs, Buffer.from(png, 'base64'));  // for whoever debugs a failure
  return page.evaluate(async (data) => {
    const image = new Image();
    image.src = `data:image/png;base64,${data}`;
    await image.decode();
    const canvas = new OffscreenCanvas(image.width, image.height);
    const context = canvas.getContext('2d');
    context.drawImage(image, 0, 0);
    const pixels = context.getImageData(0, 0, image.width, image.height).data;
    let covered = 0;
    for (let i = 0; i < pixels.length; i += 4) {
      const far = Math.abs(pixels[i] - 0x20) + Math.abs(pixels[i + 1] - 0x24) + Math.abs(pixels[i + 2] - 0x2a);
      if (far > 24) covered += 1;
    }
    return covered / (pixels.length / 4);
  }, png);
}

async function main() {
  const { child, base } = await startServer();
  let browser;
  try {
    const upload = await fetch(`${base}/v1/meshes?id=box`, { method: 'POST', body: readFileSync(sample) });
    if (upload.status !== 201) fail(`upload: ${upload.status} ${await upload.text()}`);

    browser = await puppeteer.launch({
      executablePath: chromium,
      headless: true,
      args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--window-size=800,600'],
    });
    const page = await browser.newPage();
    await page.setViewport({ width: 800, height: 600 });
    const errors = [];
    page.on('console', (message) => message.type() === 'error' && errors.push(message.text()));
    page.on('pageerror', (error) => errors.push(String(error)));
    page.on('requestfailed', (request) => errors.push(`request failed: ${request.url()}`));

    // A mesh the server does not have, while it has others: say so, and name some it has.
    await page.goto(`${base}/?mesh=no-such-mesh&relative=1e-3`);
    await page.waitForFunction(() => ['loaded', 'error'].includes(document.body.dataset.state), { timeout: 60000 });
    const missing = await page.evaluate(() => window.tesseraViewer.lastError);
    if (!missing.includes('no mesh "no-such-mesh"') || !missing.includes('box')) {
      fail(`a missing mesh reported as: ${missing}`);
    }

    await page.goto(`${base}/?mesh=box&relative=1e-3`);
    await page.waitForFunction(() => ['loaded', 'error'].includes(document.body.dataset.state), { timeout: 60000 });
    const state = await page.evaluate(() => ({ ...window.tesseraViewer }));
    if (state.phase !== 'loaded') fail(`the viewer did not load the GLB: ${state.lastError}`);
    if (!(state.triangles > 100)) fail(`only ${state.triangles} triangles`);
    await new Promise((resolve) => setTimeout(resolve, 500));  // a few animation frames
    const share = await coverage(page, path.join(work, 'viewer.png'));
    console.log(`GLB: ${state.triangles} triangles, ${state.glbBytes} bytes; silhouette covers ${(share * 100).toFixed(1)}%`);
    if (share < 0.03 || share > 0.9) fail(`the model covers ${(share * 100).toFixed(1)}% of the view`);

    // Server frames: one after switching on, another after the camera moves.
    await page.click('#serverFrames');
    await page.waitForFunction(() => window.tesseraViewer.framesReceived >= 1, { timeout: 60000 });
    const before = await page.evaluate(() => document.getElementById('frame').src);
    await page.evaluate(() => window.tesseraViewer.orbit(0.6));
    await page.waitForFunction((previous) => window.tesseraViewer.framesReceived >= 2 &&
                                 document.getElementById('frame').src !== previous, { timeout: 60000 }, before);
    const frame = await page.evaluate(() => {
      const image = document.getElementById('frame');
      return { width: image.naturalWidth, height: image.naturalHeight, error: window.tesseraViewer.lastError };
    });
    console.log(`server frames: ${JSON.stringify(frame)}`);
    await page.screenshot({ path: path.join(work, 'server-frame.png') });
    if (frame.width !== 800 || frame.height !== 600) fail(`a server frame of ${frame.width}x${frame.height}`);
    if (errors.length) fail(`console errors:\n${errors.join('\n')}`);
    console.log('web viewer: OK');
  } finally {
    if (browser) await browser.close();
    child.kill('SIGTERM');
  }
}

main().catch((error) => {
  console.error(`web viewer: FAILED: ${error.message}`);
  process.exit(1);
});
