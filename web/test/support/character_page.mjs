// What the character tests (character_e2e, retarget_e2e) share: the shared
// data files they need, and reading the viewer's character view.
import { existsSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const DATA = process.env.ARMATURE_SHARED_DATA ?? path.resolve(here, '../../../../shared/data');

// The paths of `files` (relative to ../shared/data); exits 0 with SKIP when one is missing.
export function sharedDataOrSkip(...files) {
  const paths = files.map((f) => path.join(DATA, f));
  for (const file of paths) {
    if (!existsSync(file)) {
      console.log(`SKIP: ${file} is not present (../shared/data is only beside the project's own clone)`);
      process.exit(0);
    }
  }
  return paths;
}

export const scrubTo = (page, time) => page.$eval('#scrub', (s, t) => {
  s.value = String(t);
  s.dispatchEvent(new Event('input'));
}, time);

// Two animation frames: the render loop has drawn what the scene holds now.
export const rendered = (page) =>
  page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));

// What the page draws: per mesh, its name and positions.
export const drawnPositions = (page) => page.evaluate(() =>
  window.armatureViewer.characterView.parts.map((p) => ({
    mesh: p.geometry.mesh,
    positions: Array.from(p.object.geometry.getAttribute('position').array),
  })));
