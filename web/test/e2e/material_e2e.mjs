// A textured glTF in the viewer: CesiumMan (its JPEG skin, TEXCOORD_0)
// imported over REST and shown as a mesh. Checks that the viewer builds the
// file's material (a MeshStandardMaterial with the image as its sRGB map, as
// GLTFLoader would), and, by pixel colour in Chromium, that the figure is
// drawn in the texture's colours and not the flat mesh blue: the mean
// chromaticity of its pixels matches the texture sampled at its UVs, a good
// part are the skin's white, and few are the flat blue the same view draws
// without the material. Saves both pictures: …_flat.png (no material) and the screenshot.
//   node material_e2e.mjs <armature-server> <web dir> <screenshot.png>
// SKIP when ../shared/data (or $ARMATURE_SHARED_DATA) has no cesium_man.gltf.
import { readFileSync, writeFileSync } from 'node:fs';
import { besides, check, colourStats, runViewerTest } from '../support/browser.mjs';
import { rendered, sharedDataOrSkip } from '../support/character_page.mjs';

const [GLTF] = sharedDataOrSkip('gltf/cesium_man.gltf');

// Mean chromaticity (r, g, b over their sum) of the viewport's pixels that
// differ from `empty` (the same view without the mesh), and how many.
async function figureColour(page, png, empty) {
  return page.evaluate(async ([shot, background]) => {
    const [p, q] = [(await window.decodePng(shot)).data, (await window.decodePng(background)).data];
    const sum = [0, 0, 0];
    let n = 0, white = 0;
    for (let i = 0; i < p.length; i += 4) {
      if (Math.abs(p[i] - q[i]) + Math.abs(p[i + 1] - q[i + 1]) + Math.abs(p[i + 2] - q[i + 2]) <= 30) continue;
      const total = p[i] + p[i + 1] + p[i + 2] || 1;
      for (let c = 0; c < 3; ++c) sum[c] += p[i + c] / total;
      ++n;
      // Near white (CesiumMan's skin is mostly white): bright and grey.
      const lo = Math.min(p[i], p[i + 1], p[i + 2]), hi = Math.max(p[i], p[i + 1], p[i + 2]);
      if (lo > 150 && hi - lo < 30) ++white;
    }
    return { n, white, chroma: sum.map((s) => s / Math.max(n, 1)) };
  }, [png.toString('base64'), empty.toString('base64')]);
}

// The texture's mean chromaticity at the mesh's UVs (one sample per vertex),
// decoded by the browser from the bytes the server sent.
const textureColour = (page) => page.evaluate(() => {
  const { meshView } = window.armatureViewer;
  const image = meshView.object.material[0].map.image;  // an ImageBitmap
  const canvas = new OffscreenCanvas(image.width, image.height);
  const g = canvas.getContext('2d');
  g.drawImage(image, 0, 0);
  const { data } = g.getImageData(0, 0, image.width, image.height);
  const uv = meshView.geometry.uvs;
  const sum = [0, 0, 0];
  for (let v = 0; v < uv.length; v += 2) {
    const x = Math.min(image.width - 1, Math.floor(uv[v] * image.width));
    const y = Math.min(image.height - 1, Math.floor(uv[v + 1] * image.height));  // glTF: v down the image
    const i = 4 * (y * image.width + x);
    const total = data[i] + data[i + 1] + data[i + 2] || 1;
    for (let c = 0; c < 3; ++c) sum[c] += data[i + c] / total;
  }
  return { width: image.width, height: image.height, chroma: sum.map((s) => s / (uv.length / 2)) };
});

const fmt = (c) => c.map((x) => x.toFixed(3)).join(', ');

await runViewerTest('material_e2e.mjs', async ({ page, server, screenshot }) => {
  const asset = await server.importAsset('cesium_man.gltf', 'cesium', readFileSync(GLTF));
  const mesh = asset.meshes[0].name;
  const clip = asset.clips[0].name;
  await page.goto(`${server.url}/?mesh=${encodeURIComponent(mesh)}&clip=${encodeURIComponent(clip)}`);
  await page.waitForFunction(() => window.armatureViewer?.meshPlayer.stats.evaluations > 0, null, { timeout: 60000 });
  const textured = await page.evaluate(() => window.armatureViewer.meshView.materialsReady);
  const built = await page.evaluate(() => {
    const [m] = [window.armatureViewer.meshView.object.material].flat();
    return { type: m.type, name: m.name, map: !!m.map, colorSpace: m.map?.colorSpace, flipY: m.map?.flipY,
             metalness: m.metalness, roughness: m.roughness, uvs: window.armatureViewer.meshView.object.geometry.getAttribute('uv')?.count };
  });
  check(textured && built.type === 'MeshStandardMaterial' && built.name === 'Cesium_Man-effect' && built.map &&
        built.colorSpace === 'srgb' && built.flipY === false && built.metalness === 0 && built.roughness === 1 &&
        built.uvs === 3273,
        `the viewer builds the file's material as GLTFLoader would (${JSON.stringify(built)})`);

  await rendered(page);
  const png = await page.locator('#viewport').screenshot();
  // The same view: without the mesh (the background), then flat (no material).
  const swap = (mode) => page.evaluate((m) => {
    const { object } = window.armatureViewer.meshView;
    object.userData.fileMaterials ??= object.material;
    object.visible = m !== 'hidden';
    object.material = m === 'flat' ? object.userData.fileMaterials.at(-1) : object.userData.fileMaterials;
  }, mode);
  await swap('hidden');
  await rendered(page);
  const empty = await page.locator('#viewport').screenshot();
  await swap('flat');
  await rendered(page);
  const flatPng = await page.locator('#viewport').screenshot();
  await swap('textured');
  await rendered(page);
  writeFileSync(besides(screenshot, 'flat'), flatPng);
  writeFileSync(screenshot, png);

  const blueTextured = (await colourStats(page, png, 'mesh')).count;  // (defines the page's PNG decoder)
  const blueFlat = (await colourStats(page, flatPng, 'mesh')).count;
  const texture = await textureColour(page);
  const drawn = await figureColour(page, png, empty);
  const flat = await figureColour(page, flatPng, empty);
  const distance = (a, b) => Math.max(...a.map((x, c) => Math.abs(x - b[c])));
  check(drawn.n > 2000 && distance(drawn.chroma, texture.chroma) < 0.025,
        `the figure's ${drawn.n} pixels have the texture's colour: chromaticity (${fmt(drawn.chroma)}) against ` +
        `the ${texture.width}×${texture.height} JPEG's (${fmt(texture.chroma)}) at the UVs`);
  check(distance(flat.chroma, texture.chroma) > 0.045,
        `drawn flat, the figure's colour (${fmt(flat.chroma)}) is not the texture's: the check tells them apart`);
  check(blueFlat > 0.8 * flat.n && flat.white < 0.02 * flat.n && blueTextured < 0.3 * blueFlat && drawn.white > 0.3 * drawn.n,
        `textured, ${drawn.white} of the figure's ${drawn.n} pixels are the skin's white and ${blueTextured} blue ` +
        `(its blue patches); drawn flat, ${blueFlat} of ${flat.n} are the flat mesh blue and ${flat.white} white`);
});
