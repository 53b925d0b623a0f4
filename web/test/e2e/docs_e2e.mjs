// The API reference at /docs: swagger-ui (swagger-ui-dist, served by the
// server itself) renders the server's /openapi.json: one entry per operation,
// under the document's title, with every request to the server's own origin
// (no CDN).
//   node docs_e2e.mjs <armature-server> <web dir> <screenshot.png>
import { check, runViewerTest } from '../support/browser.mjs';

await runViewerTest('docs_e2e.mjs', async ({ page, server, screenshot }) => {
  const spec = await (await fetch(`${server.url}/openapi.json`)).json();
  const methods = new Set(['get', 'put', 'post', 'delete', 'patch']);
  const operations = Object.values(spec.paths).reduce(
    (n, item) => n + Object.keys(item).filter((m) => methods.has(m)).length, 0);
  const origins = new Set();
  page.on('request', (r) => origins.add(new URL(r.url()).origin));

  await page.goto(`${server.url}/docs`);
  check(new URL(page.url()).pathname === '/docs/', `/docs leads to the reference (${page.url()})`);
  await page.waitForFunction((n) => document.querySelectorAll('.opblock').length >= n, operations, { timeout: 60000 });
  const shown = await page.$$eval('.opblock', (ops) => ops.length);
  check(shown === operations, `every operation of /openapi.json is listed (${shown} of ${operations})`);
  const title = (await page.textContent('.info .title')) ?? '';
  check(title.includes(spec.info.title), `under the document's title ("${title.trim()}")`);
  const evaluate = await page.$$eval('.opblock-summary-path', (ps) => ps.map((p) => p.textContent));
  check(evaluate.some((p) => p.includes('/v1/clips/{clip}:evaluate')), 'the clip evaluation route is among them');
  check([...origins].every((o) => o === server.url), `no request leaves the server (${[...origins].join(', ')})`);
  await page.screenshot({ path: screenshot });
});
