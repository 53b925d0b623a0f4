// Drag-and-drop import in the viewer: files dropped on the page (a DataTransfer
// with File objects, as the browser builds one for a drop from the desktop) go
// to POST /v1/assets:import. A small BVH appears in the clip picker and plays;
// the skinned tube (.gltf, fixtures.mjs) appears in the character picker and
// is shown whole; the progress indicator reaches 100% and hides; a file the
// server refuses shows its message. Saves a screenshot.
//   node drop_e2e.mjs <armature-server> <web dir> <screenshot.png>
import { check, colourStats, runViewerTest } from '../support/browser.mjs';
import { ARM_BVH, twistTubeGltf } from '../support/fixtures.mjs';

// Drops files [{ name, text }] on the page, as dragenter, dragover and drop events.
async function drop(page, files) {
  const transfer = await page.evaluateHandle((list) => {
    const dt = new DataTransfer();
    for (const { name, text } of list) dt.items.add(new File([text], name, { type: 'application/octet-stream' }));
    return dt;
  }, files);
  for (const type of ['dragenter', 'dragover']) await page.dispatchEvent('body', type, { dataTransfer: transfer });
  const highlighted = await page.evaluate(() => document.body.classList.contains('dropping'));
  await page.dispatchEvent('body', 'drop', { dataTransfer: transfer });
  return highlighted;
}

// The progress fractions the page reported since the last call, and the indicator's state now.
const progressSeen = (page) => page.evaluate(() => {
  const seen = window.progressSeen.splice(0);
  return { seen, hidden: document.getElementById('import-progress').hidden, label: document.getElementById('import-label').textContent };
});

await runViewerTest('drop_e2e.mjs', async ({ page, server, screenshot, expectConsoleError }) => {
  await page.goto(server.url + '/?clip=demo_walk');
  await page.waitForFunction(() => window.armatureViewer?.player.skeleton, null, { timeout: 30000 });
  await page.evaluate(() => {
    window.progressSeen = [];
    window.armatureViewer.dropImport.addEventListener('progress', ({ detail }) => window.progressSeen.push(detail));
  });

  // A BVH: its clip joins the picker and plays on its skeleton.
  const highlighted = await drop(page, [{ name: 'dropped_arm.bvh', text: ARM_BVH }]);
  check(highlighted, 'dragging files over the page highlights it');
  await page.waitForFunction(() => window.armatureViewer.player.clip?.name === 'dropped_arm', null, { timeout: 30000 });
  const clips = await page.$$eval('#clip option', (os) => os.map((o) => o.value));
  const joints = await page.textContent('#joints');
  check(clips.includes('dropped_arm') && joints === '2 joints',
        `the dropped BVH is in the clip picker and shown (${clips.length} clips; ${joints})`);
  let progress = await progressSeen(page);
  check(progress.seen.at(-1) === 1 && progress.hidden && progress.label === 'Imported dropped_arm',
        `the progress went ${progress.seen.map((f) => f.toFixed(2)).join(' → ')}, then hid ("${progress.label}")`);
  const listed = (await (await fetch(`${server.url}/v1/clips`)).json()).clips.map((c) => c.name);
  check(listed.includes('dropped_arm'), 'the server lists the dropped clip');

  // A skinned .gltf: a new character, shown whole.
  const tube = twistTubeGltf();
  await drop(page, [{ name: 'dropped_tube.gltf', text: tube.text }]);
  await page.waitForFunction(() => {
    const { characterPlayer } = window.armatureViewer;
    return characterPlayer.character?.skeleton === 'dropped_tube' && characterPlayer.stats.evaluations > 0;
  }, null, { timeout: 30000 });
  const characters = await page.$$eval('#character option', (os) => os.map((o) => o.textContent));
  const chosen = await page.$eval('#character', (s) => s.value);
  check(characters.includes('dropped_tube (1 mesh)') && chosen === 'dropped_tube',
        `the dropped glTF is a character in the picker, chosen (${characters.join(', ')})`);
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const png = await page.locator('#viewport').screenshot();
  const stats = await colourStats(page, png, 'character');
  check(stats.count > 500, `the tube is drawn (${stats.count} pixels, ${stats.width}×${stats.height})`);
  progress = await progressSeen(page);
  check(progress.seen.at(-1) === 1 && progress.hidden, 'its progress reached 100% and hid');

  // A file the server refuses: its message is shown, nothing else changes.
  expectConsoleError(/400|Bad Request/);
  await drop(page, [{ name: 'broken.bvh', text: 'HIERARCHY\nROOT\n' }]);
  await page.waitForFunction(() => document.getElementById('message').textContent.startsWith('Import:'), null, { timeout: 30000 });
  const message = await page.textContent('#message');
  const label = await page.textContent('#import-label');
  check(label === 'Import of broken.bvh failed' && message.length > 'Import: '.length,
        `a broken file is refused with the server's message ("${message}")`);
  await page.screenshot({ path: screenshot });
});
