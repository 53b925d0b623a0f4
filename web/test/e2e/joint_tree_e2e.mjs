// The joint hierarchy panel on the demo walk: every joint's name, indented
// under its parent; the joint under the pointer in the view is highlighted in
// the list (and ringed in the view), pointing at a name rings its joint, and
// leaving the view clears both.
//   node joint_tree_e2e.mjs <armature-server> <web dir> <screenshot.png>
import { check, runViewerTest } from '../support/browser.mjs';

await runViewerTest('joint_tree_e2e.mjs', async ({ page, server, screenshot }) => {
  const skeleton = await (await fetch(`${server.url}/v1/skeletons/demo_walk`)).json();
  await page.goto(`${server.url}/?clip=demo_walk`);
  await page.waitForFunction(() => window.armatureViewer?.player.skeleton, null, { timeout: 30000 });
  // Paused (as the page opens): the joints stay where the pointer goes.
  await page.waitForFunction(() => !window.armatureViewer.player.playing && window.armatureViewer.view.joints.length > 0);

  check(await page.isVisible('#joint-tree'), 'the joint list shows beside the skeleton');
  const items = await page.$$eval('#joint-tree li', (lis) => lis.map((li) => ({
    name: li.textContent, indent: parseFloat(getComputedStyle(li).paddingLeft) })));
  const names = skeleton.joints.map((j) => j.name);
  check(JSON.stringify(items.map((i) => i.name)) === JSON.stringify(names),
        `it names the ${names.length} joints in the skeleton's order`);
  const indent = (name) => items[names.indexOf(name)].indent;
  check(indent('LeftKnee') > indent('LeftHip') && indent('LeftHip') > indent('Hips') &&
        indent('Head') > indent('Neck'), 'each joint is indented under its parent');

  const head = names.indexOf('Head');
  const at = await page.evaluate((i) => window.armatureViewer.ik.screenPosition(i), head);
  await page.mouse.move(at.x, at.y);
  await page.waitForFunction((i) => window.armatureViewer.jointTree.hovered === i, head, { timeout: 5000 });
  const hovered = await page.$$eval('#joint-tree li.hovered', (lis) => lis.map((li) => li.textContent));
  const ringed = await page.evaluate(() => window.armatureViewer.jointTree.marker.visible);
  check(hovered.length === 1 && hovered[0] === 'Head' && ringed,
        `the pointer on Head's sphere highlights Head in the list and rings it (${hovered})`);
  await page.screenshot({ path: screenshot });

  await page.hover(`#joint-tree li[data-joint="${names.indexOf('LeftKnee')}"]`);
  const fromList = await page.evaluate(() => {
    const { jointTree, view } = window.armatureViewer;
    return { hovered: jointTree.hovered, at: jointTree.marker.position.distanceTo(view.joints[jointTree.hovered].position) };
  });
  check(fromList.hovered === names.indexOf('LeftKnee') && fromList.at < 1e-6,
        'pointing at LeftKnee in the list rings LeftKnee in the view');

  const viewport = await page.$eval('#viewport canvas', (c) => c.getBoundingClientRect().toJSON());
  await page.mouse.move(viewport.right - 5, viewport.bottom - 5);
  await page.waitForFunction(() => window.armatureViewer.jointTree.hovered === -1, null, { timeout: 5000 });
  check(await page.$$eval('#joint-tree li.hovered', (lis) => lis.length) === 0, 'away from every joint nothing is highlighted');
});
