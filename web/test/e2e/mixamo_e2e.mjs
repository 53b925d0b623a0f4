// A Mixamo-style rig in the viewer: RobotExpressive under an `Armature` node
// at scale 0.01 with its joints in centimetres (mixamo_rig.mjs), imported
// over REST. The skeleton view, the blend view and the skeleton drawn over a
// mesh are sized from the posed world positions: the joint spheres cover a
// sliver of the picture (not the whole of it), the bones show with a body's
// extent, and the grid spreads under the figure. Saves screenshots.
//   node mixamo_e2e.mjs <armature-server> <web dir> <screenshot.png>
// SKIP when ../shared/data (or $ARMATURE_SHARED_DATA) has no RobotExpressive.
import { readFileSync } from 'node:fs';
import { besides, check, colourStats, runViewerTest } from '../support/browser.mjs';
import { sharedDataOrSkip } from '../support/character_page.mjs';
import { mixamoRigGlb } from '../support/mixamo_rig.mjs';

const [GLB] = sharedDataOrSkip('gltf/RobotExpressive/RobotExpressive.glb');

// The 3D view's picture alone (the controls around it have white too).
const viewport = async (page) => page.screenshot({ clip: await page.locator('#viewport').boundingBox() });

// The picture's joint-white and bone pixels, and the view's sizes against the figure's.
// `framed`: the camera frames the skeleton (over a mesh it frames the mesh).
async function coverage(page, png, what, { framed = true } = {}) {
  const joints = await colourStats(page, png, 'joint');
  const bones = await colourStats(page, png, 'bone');
  const sizes = await page.evaluate(() => {
    const { view } = window.armatureViewer;
    const ys = view.joints.map((j) => j.position.y);
    return { radius: view.radius, height: Math.max(...ys) - Math.min(...ys), gridCell: view.grid?.userData.cell };
  });
  const share = joints.count / joints.pixels;
  check(share < 0.02, `${what}: joint spheres cover ${(100 * share).toFixed(2)} % of the picture`);
  check(bones.count > 300 && bones.height > 0.15 * bones.imageHeight && (!framed || bones.height < 0.95 * bones.imageHeight),
    `${what}: the bones show with a body's extent (${bones.count} px, ${bones.width}×${bones.height} px)`);
  check(sizes.radius < 0.02 * sizes.height,
    `${what}: the bone radius is ${(sizes.radius / sizes.height).toExponential(2)} of the figure's height`);
  return sizes;
}

await runViewerTest('mixamo_e2e.mjs', async ({ page, server, screenshot }) => {
  const asset = await server.importAsset('mixamo.glb', 'mixamo', mixamoRigGlb(readFileSync(GLB)));
  const skeleton = await server.call('/v1/skeletons/mixamo');
  const armature = skeleton.joints.find((j) => j.name === 'Armature');
  check(armature && Math.abs(armature.restScale[0] - 0.01) < 1e-6,
    `the rig's Armature node is at scale ${armature?.restScale?.[0]}`);

  // The skeleton view.
  await page.goto(server.url + '/?clip=mixamo.Idle');
  await page.waitForFunction(() => /^t = /.test(document.getElementById('time').textContent), null, { timeout: 30000 });
  await page.screenshot({ path: screenshot });
  const alone = await viewport(page);
  const sizes = await coverage(page, alone, 'skeleton view');
  const grid = await colourStats(page, alone, 'grid');
  check(sizes.gridCell * 48 > 2 * sizes.height && sizes.gridCell * 48 < 50 * sizes.height,
    `the grid is ${(sizes.gridCell * 48 / sizes.height).toFixed(1)} figure heights across`);
  check(grid.width > 0.6 * grid.imageWidth && grid.height > 0.25 * grid.imageHeight,
    `the grid spreads under the figure (${grid.width}×${grid.height} px), not a clipped strip`);

  // The blend view (the same skeleton, drawn by EvaluateMotion).
  await page.click('#blend');
  await page.waitForFunction(() => window.armatureViewer.blend.last, null, { timeout: 30000 });
  await page.screenshot({ path: besides(screenshot, 'blend') });
  await coverage(page, await viewport(page), 'blend view');
  await page.click('#blend');

  // The skeleton over a mesh of the rig.
  const mesh = asset.meshes.filter((m) => m.skeleton === 'mixamo').sort((a, b) => b.vertexCount - a.vertexCount)[0];
  await page.goto(server.url + `/?mesh=${encodeURIComponent(mesh.name)}&clip=mixamo.Idle`);
  await page.waitForFunction(() => window.armatureViewer?.meshView.lastCenter && window.armatureViewer.player.clip,
    null, { timeout: 30000 });
  await page.screenshot({ path: besides(screenshot, 'mesh') });
  await coverage(page, await viewport(page), `mesh view (${mesh.name})`, { framed: false });
});
