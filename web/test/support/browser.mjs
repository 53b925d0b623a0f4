// What the browser tests share: the command line, a real armature-server,
// headless Chromium (Debian's, driven by playwright-core) with console errors
// collected, checks that print what they measured, and pixel counts of
// screenshots.
import { existsSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';
import { startServer } from './server.mjs';

const CHROMIUM = process.env.ARMATURE_CHROMIUM ?? '/usr/bin/chromium';

export function check(condition, message) {
  if (!condition) throw new Error(message);
  console.log(`ok: ${message}`);
}

// Runs `body({ page, server, screenshot, expectConsoleError })` against a
// fresh server and browser, for `node <test>.mjs <armature-server> <web dir>
// <screenshot.png>`; fails on any console error, page error or failed
// request, and exits with the result. `expectConsoleError(regex)` allows one
// console error matching it (a request the test makes fail on purpose). SKIP (exit 0) when Chromium is not installed.
export async function runViewerTest(script, body) {
  const [serverBin, webDir, screenshot] = process.argv.slice(2);
  if (!serverBin || !webDir || !screenshot) {
    console.error(`usage: node ${script} <armature-server> <web dir> <screenshot.png>`);
    process.exit(2);
  }
  if (!existsSync(CHROMIUM)) {
    console.log(`SKIP: ${CHROMIUM} is not installed (Debian packages chromium and chromium-driver; scripts/setup.sh test)`);
    process.exit(0);
  }
  if (!existsSync(path.join(webDir, 'index.html'))) {
    console.error(`FAIL: no viewer in ${webDir} (build the armature_web target)`);
    process.exit(1);
  }
  mkdirSync(path.dirname(path.resolve(screenshot)), { recursive: true });
  const server = await startServer(serverBin, ['--web-dir', webDir]);
  const profile = mkdtempSync(path.join(tmpdir(), 'armature-chromium-'));
  let context;
  let failed = false;
  try {
    context = await chromium.launchPersistentContext(profile, {
      executablePath: CHROMIUM,
      headless: true,
      viewport: { width: 1024, height: 700 },
      args: [
        '--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
        '--disable-sync', '--no-first-run',
        // No GPU: WebGL on the CPU.
        '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      ],
    });
    const page = context.pages()[0] ?? (await context.newPage());
    const problems = [];
    const expected = [];
    page.on('console', (m) => {
      if (m.type() !== 'error') return;
      const allowed = expected.findIndex((re) => re.test(m.text()));
      if (allowed >= 0) expected.splice(allowed, 1);
      else problems.push(`console: ${m.text()}`);
    });
    page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
    // Leaving a page aborts the old document's requests in flight: while a
    // test navigates, an aborted request is no error.
    let navigating = 0;
    const goto = page.goto.bind(page);
    page.goto = async (...args) => {
      navigating += 1;
      try {
        return await goto(...args);
      } finally {
        navigating -= 1;
      }
    };
    page.on('requestfailed', (r) => {
      // Closing a stream (pause, a new stream) aborts its gRPC-Web request: that is no error either.
      const stream = /\/armature\.v1\.\w+\/Stream\w+$/.test(r.url()) || r.url().includes(':stream');
      if (stream && r.failure()?.errorText === 'net::ERR_ABORTED') return;
      if (navigating > 0 && r.failure()?.errorText === 'net::ERR_ABORTED') return;
      problems.push(`request failed: ${r.url()} ${r.failure()?.errorText}`);
    });
    await body({ page, server, screenshot, expectConsoleError: (re) => expected.push(re) });
    check(problems.length === 0, `no console errors${problems.length ? ':\n  ' + problems.join('\n  ') : ''}`);
    console.log(`screenshot: ${path.resolve(screenshot)}`);
  } catch (error) {
    failed = true;
    console.error(`FAIL: ${error.message}`);
    console.error(server.log().split('\n').slice(-20).join('\n'));
  } finally {
    await context?.close();
    await server.stop();
    rmSync(profile, { recursive: true, force: true });
  }
  process.exit(failed ? 1 : 0);
}

// `screenshot` with `suffix` before .png: viewer.png → viewer_ik.png.
export function besides(screenshot, suffix) {
  return screenshot.replace(/\.png$/, '') + `_${suffix}.png`;
}

// Defines window.decodePng(base64) → ImageData in the page: the browser
// decodes the screenshots (node has no PNG decoder here).
function definePngDecoder(page) {
  return page.evaluate(() => {
    window.decodePng ??= async (base64) => {
      const image = new Image();
      image.src = `data:image/png;base64,${base64}`;
      await image.decode();
      const canvas = document.createElement('canvas');
      canvas.width = image.width;
      canvas.height = image.height;
      const g = canvas.getContext('2d');
      g.drawImage(image, 0, 0);
      return g.getImageData(0, 0, image.width, image.height);
    };
  });
}

// Counts the pixels of a PNG screenshot (decoded by the browser) close to a
// colour the viewer draws: 'bone' (#ff8c1a), 'mesh' (#8fb3d9) or 'character' (any
// of CharacterView's shades), 'joint' (the joints' near white) or 'grid' (its
// greys), however lit; and their bounding box, and the image's size.
export async function colourStats(page, png, colour) {
  await definePngDecoder(page);
  return page.evaluate(async ({ base64, colour }) => {
    const looksLike = {
      // Red high, green middling, blue low.
      bone: (r, g, b) => r > 140 && g > 50 && g < 0.8 * r && b < 0.45 * r,
      // Blue above green above red, clearly saturated (the grid is grey).
      mesh: (r, g, b) => b > 60 && g > r && b > g && b - r > 0.25 * b,
      // Any of a character's shades: coloured and not dark (the grid and the background are grey).
      character: (r, g, b) => Math.max(r, g, b) > 60 && Math.max(r, g, b) - Math.min(r, g, b) > 0.3 * Math.max(r, g, b),
      joint: (r, g, b) => Math.min(r, g, b) > 190,
      // Bluish greys brighter than the background (#1c1f24), dimmer than the joints.
      grid: (r, g, b) => b >= g && g >= r && b - r < 30 && b > 48 && b < 150,
    }[colour];
    const { data, width, height } = await window.decodePng(base64);
    let count = 0, minX = Infinity, maxX = -1, minY = Infinity, maxY = -1;
    for (let i = 0; i < data.length; i += 4) {
      if (!looksLike(data[i], data[i + 1], data[i + 2])) continue;
      ++count;
      const p = i / 4, x = p % width, y = Math.floor(p / width);
      minX = Math.min(minX, x); maxX = Math.max(maxX, x);
      minY = Math.min(minY, y); maxY = Math.max(maxY, y);
    }
    return { count, width: maxX - minX + 1, height: maxY - minY + 1, pixels: data.length / 4,
             imageWidth: width, imageHeight: height };
  }, { base64: png.toString('base64'), colour });
}

// The pixels that differ (summed channel difference over 30) between two PNG screenshots of one size.
export async function changedPixels(page, a, b) {
  await definePngDecoder(page);
  return page.evaluate(async ([first, second]) => {
    const [p, q] = [(await window.decodePng(first)).data, (await window.decodePng(second)).data];
    let n = 0;
    for (let i = 0; i < p.length; i += 4)
      if (Math.abs(p[i] - q[i]) + Math.abs(p[i + 1] - q[i + 1]) + Math.abs(p[i + 2] - q[i + 2]) > 30) ++n;
    return n;
  }, [a.toString('base64'), b.toString('base64')]);
}

// Runs `action`, then waits until window.armatureViewer[name] (a Playback, or
// anything with stats.evaluations and a LatestWins sampler) has shown a new
// answer and has none in flight.
export async function answeredAfter(page, name, action) {
  const before = await page.evaluate((n) => window.armatureViewer[n].stats.evaluations, name);
  await action();
  await page.waitForFunction(([n, count]) => {
    const player = window.armatureViewer[n];
    return player.stats.evaluations > count && !player.sampler.busy;
  }, [name, before], { timeout: 30000 });
}
