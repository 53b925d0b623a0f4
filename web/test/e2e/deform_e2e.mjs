// Dragging a vertex in the viewer (Laplacian editing), end to end: the test
// makes a 40×40 grid with a bump (fixtures.mjs), imports it as an .obj over
// REST, chooses it (no skin, no morphs: shown at rest), turns on edit mode
// and drags vertices with the mouse. Checks that Deform calls ran, that the
// dragged vertex is drawn under the pointer at its target, that vertices
// outside the region of interest did not move while those near the handle
// followed, that a second drag keeps the first handle's target (edits
// accumulate), ARAP and cotangent weights, and Reset. Saves a screenshot.
//   node deform_e2e.mjs <armature-server> <web dir> <screenshot.png>
import { check, colourStats, runViewerTest } from '../support/browser.mjs';
import { bumpGridObj } from '../support/fixtures.mjs';

const grid = bumpGridObj();
const MESH = 'plane';
const vertex = (i, j) => i * grid.n + j;
const fmt = (x) => x.toFixed(5);

// In the page: where things are now, for the vertices asked about.
function measure(indices) {
  const { meshView, vertexDrag } = window.armatureViewer;
  const rest = Float32Array.from(meshView.geometry.positions);  // as drawn: float32
  const region = new Set(vertexDrag.regionOfInterest());
  let outsideMoved = 0, insideMoved = 0;
  for (let v = 0; v < meshView.vertexCount; ++v) {
    const p = meshView.vertexPosition(v);
    const moved = Math.hypot(p.x - rest[3 * v], p.y - rest[3 * v + 1], p.z - rest[3 * v + 2]);
    if (region.has(v)) insideMoved += moved > 1e-4;
    else outsideMoved = Math.max(outsideMoved, moved);
  }
  const at = (v) => meshView.vertexPosition(v).toArray();
  return {
    region: region.size,
    outsideMoved,
    insideMoved,
    deforms: vertexDrag.stats.deforms,
    handles: [...vertexDrag.handles.keys()],
    markers: vertexDrag.markers.children.map((m) => m.position.toArray()),
    vertices: Object.fromEntries(indices.map((v) => [v, {
      rest: Array.from(rest.subarray(3 * v, 3 * v + 3)),
      now: at(v),
      target: vertexDrag.handles.get(v)?.toArray() ?? null,
      screen: vertexDrag.screenPosition(v),
    }])),
    rate: document.getElementById('rate').textContent,
    message: document.getElementById('message').textContent,
  };
}

const distance = (a, b) => Math.hypot(...a.map((x, k) => x - b[k]));

// Drags vertex `index` by (dx, dy) pixels with the mouse; returns where the pointer let go.
async function dragVertex(page, index, dx, dy) {
  const at = await page.evaluate((v) => window.armatureViewer.vertexDrag.screenPosition(v), index);
  const picked = await page.evaluate(({ x, y }) => window.armatureViewer.vertexDrag.pick({ clientX: x, clientY: y }), at);
  check(picked === index, `vertex ${index} is picked at its screen position (${at.x.toFixed(1)}, ${at.y.toFixed(1)})`);
  const drop = { x: at.x + dx, y: at.y + dy };
  const before = await page.evaluate(() => window.armatureViewer.vertexDrag.stats.deforms);
  await page.mouse.move(at.x, at.y);
  await page.mouse.down();
  // Three legs, each waited for, so a slow (loaded) browser still sends a Deform per leg:
  // latest-wins may merge the moves inside a leg, never across legs.
  let last = before;
  for (const f of [1 / 3, 2 / 3, 1]) {
    await page.mouse.move(at.x + dx * f, at.y + dy * f, { steps: 7 });
    if (f < 1) {
      await page.waitForFunction((n) => {
        const { vertexDrag } = window.armatureViewer;
        return vertexDrag.stats.deforms > n && !vertexDrag.busy;
      }, last, { timeout: 30000 });
      last = await page.evaluate(() => window.armatureViewer.vertexDrag.stats.deforms);
    }
  }
  await page.mouse.up();
  await settled(page, last);
  return drop;
}

// Waits until a Deform newer than `before` answered and none is left to run.
async function settled(page, before) {
  await page.waitForFunction((n) => {
    const { vertexDrag } = window.armatureViewer;
    return vertexDrag.stats.deforms > n && !vertexDrag.busy && !vertexDrag.drag;
  }, before, { timeout: 30000 });
}

await runViewerTest('deform_e2e.mjs', async ({ page, server, screenshot }) => {
  const asset = await server.importAsset('plane.obj', MESH, grid.text);
  check(asset.meshes?.[0]?.name === MESH && asset.meshes[0].vertexCount === grid.vertexCount,
        `the grid imports over REST (${asset.meshes?.[0]?.vertexCount} vertices, ${asset.meshes?.[0]?.triangleCount} triangles)`);

  await page.goto(server.url + '/?clip=demo_walk');
  await page.waitForFunction(() => window.armatureViewer?.player.skeleton, null, { timeout: 30000 });
  await page.selectOption('#mesh', MESH);
  await page.waitForFunction((mesh) => window.armatureViewer.meshView.geometry?.mesh === mesh, MESH, { timeout: 30000 });
  const rest = await page.evaluate(() => ({
    time: document.getElementById('time').textContent,
    play: document.getElementById('play').disabled,
    clip: document.getElementById('clip').disabled,
  }));
  check(rest.time === 'at rest' && rest.play && rest.clip, 'a mesh without skin or morphs is shown at rest, nothing to play');
  const restShot = await page.screenshot();
  const drawn = await colourStats(page, restShot, 'mesh');
  check(drawn.count > 20000, `the grid is drawn (${drawn.count} mesh-coloured pixels)`);

  await page.check('#edit');
  await page.waitForFunction(() => window.armatureViewer.vertexDrag.editing);
  check(!(await page.$eval('#edit-controls', (e) => e.hidden)), 'edit mode shows its controls');

  // Drag the top of the bump up and to the right.
  const A = vertex(20, 20);
  const B = vertex(20, 8);
  const dropA = await dragVertex(page, A, 40, -90);
  const first = await page.evaluate(measure, [A, vertex(20, 21), B]);
  const a = first.vertices[A];
  const neighbour = first.vertices[vertex(20, 21)];
  const moved = distance(a.now, a.rest);
  const followed = distance(neighbour.now, neighbour.rest) / moved;
  check(first.deforms >= 3, `dragging ran Deform calls (${first.deforms})`);
  check(distance(a.now, a.target) < 1e-5 && moved > 0.2,
        `the dragged vertex is at its target (${fmt(distance(a.now, a.target))} away) after moving ${fmt(moved)}`);
  const miss = Math.hypot(a.screen.x - dropA.x, a.screen.y - dropA.y);
  check(miss < 2, `the dragged vertex is drawn under the pointer (${miss.toFixed(2)} px away)`);
  check(first.outsideMoved === 0 && first.region < grid.vertexCount / 2,
        `vertices outside the region (${grid.vertexCount - first.region} of ${grid.vertexCount}) did not move ` +
        `(largest shift ${first.outsideMoved})`);
  check(first.insideMoved > 100 && followed > 0.5,
        `the surface around it followed (${first.insideMoved} vertices moved; the next vertex by ` +
        `${(followed * 100).toFixed(0)}% of the handle's shift)`);
  check(first.markers.length === 1 && distance(first.markers[0], a.target) < 1e-9, 'a marker shows the handle');
  check(/^deform \d+\.\d ms$/.test(first.rate) && /Deform: 1 handle, \d+ vertices/.test(first.message),
        `the HUD shows the round trip (${first.rate}; ${first.message})`);

  // A second drag elsewhere: the first handle keeps its target.
  const dropB = await dragVertex(page, B, 0, 50);
  const second = await page.evaluate(measure, [A, B]);
  const [a2, b2] = [second.vertices[A], second.vertices[B]];
  const missB = Math.hypot(b2.screen.x - dropB.x, b2.screen.y - dropB.y);
  check(second.handles.length === 2 && distance(a2.now, a.target) < 1e-5 && distance(b2.now, b2.target) < 1e-5 &&
        missB < 2, `edits accumulate: both handles sit on their targets (the second ${missB.toFixed(2)} px from the pointer)`);
  check(second.outsideMoved === 0, `still nothing outside the region moved (${second.region} vertices in it)`);

  // ARAP, then cotangent weights: solved again with the same handles.
  const laplacian = await page.evaluate(() => window.armatureViewer.meshView.object.geometry.getAttribute('position').array.slice());
  let before = second.deforms;
  await page.selectOption('#deform-method', 'ARAP');
  await settled(page, before);
  const arap = await page.evaluate(measure, [A, B]);
  const arapShift = await page.evaluate((old) => {
    const now = window.armatureViewer.meshView.object.geometry.getAttribute('position').array;
    return Math.max(...Array.from(now, (x, i) => Math.abs(x - old[i])));
  }, laplacian);
  check(/ARAP iterations/.test(arap.message) && arapShift > 1e-3 &&
        distance(arap.vertices[A].now, a.target) < 1e-5 && distance(arap.vertices[B].now, b2.target) < 1e-5,
        `ARAP keeps the handles and changes the shape (by up to ${fmt(arapShift)}; ${arap.message})`);
  before = arap.deforms;
  await page.selectOption('#deform-weights', 'COTANGENT');
  await settled(page, before);
  const cotangent = await page.evaluate(measure, [A, B]);
  check(distance(cotangent.vertices[A].now, a.target) < 1e-5 && cotangent.outsideMoved === 0,
        `cotangent weights: the handles hold, the outside stays (${cotangent.rate})`);
  await page.screenshot({ path: screenshot });

  // Reset: the rest shape, no handles.
  await page.click('#reset');
  const reset = await page.evaluate(measure, [A]);
  check(reset.handles.length === 0 && reset.markers.length === 0 && distance(reset.vertices[A].now, a.rest) === 0,
        'Reset goes back to the rest shape');
});
