// What a newcomer sees first, on the demo assets alone: at 1200 px every
// header row stays on one line (with the character, the Retarget row and a
// long asset name shown), and the Retarget panel offers the demo walk (a
// clip of another body) for the demo character, then forgets its answer when
// another character is chosen.
//   node first_look_e2e.mjs <armature-server> <web dir> <screenshot.png>
import { check, runViewerTest } from '../support/browser.mjs';
import { ARM_BVH } from '../support/fixtures.mjs';

const LONG = 'a_capture_with_a_rather_long_descriptive_name_from_the_mocap_stage';

// Each visible header row: its height in lines of its first control, and whether it overflows.
function headerRows(page) {
  return page.$$eval('#controls .row', (rows) => rows.filter((r) => r.offsetParent !== null).map((r) => {
    const tops = [...r.children].filter((c) => c.offsetParent !== null).map((c) => c.getBoundingClientRect());
    const lineHeight = Math.max(...tops.map((b) => b.height));
    return { id: r.id || 'the first',
             lines: r.getBoundingClientRect().height / lineHeight, overflow: r.scrollWidth - r.clientWidth };
  }));
}

await runViewerTest('first_look_e2e.mjs', async ({ page, server, screenshot }) => {
  // A clip with a long name (a two-joint arm, no body to retarget from): it widens the clip pickers.
  await server.importAsset('long.bvh', LONG, Buffer.from(ARM_BVH));
  await page.setViewportSize({ width: 1200, height: 800 });
  await page.goto(`${server.url}/?character=demo_character`);
  await page.waitForFunction(() => window.armatureViewer?.characterPlayer?.character, null, { timeout: 60000 });
  const rows = await headerRows(page);
  check(rows.length >= 2, `the character's header rows show (${rows.map((r) => r.id).join(', ')})`);
  for (const r of rows)
    check(r.lines < 1.6 && r.overflow <= 0,
          `at 1200 px header row ${r.id} is one line (${r.lines.toFixed(2)} lines, overflow ${r.overflow} px)`);

  await page.waitForFunction(() => window.armatureViewer.retarget.defaulted > 0, null, { timeout: 30000 });
  const source = await page.inputValue('#retarget-source');
  check(source === 'demo_walk', `Retarget offers demo_walk for demo_character first (${source})`);
  await page.click('#retarget-run');
  await page.waitForFunction(() => window.armatureViewer.retarget.calls > 0 && !window.armatureViewer.retarget.busy,
                             null, { timeout: 60000 });
  const shown = await page.textContent('#retarget-result');
  check(/pairs mapped/.test(shown), `Retarget answered: "${shown}"`);
  await page.screenshot({ path: screenshot });

  await page.selectOption('#character', '');
  await page.waitForFunction(() => window.armatureViewer.retarget.skeleton === '', null, { timeout: 30000 });
  const cleared = await page.textContent('#retarget-result');
  const last = await page.evaluate(() => window.armatureViewer.retarget.last);
  check(cleared === '' && last === null, `another character clears the answer ("${cleared}")`);
});
