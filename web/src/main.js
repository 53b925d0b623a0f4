// The viewer page: choose a clip (and a mesh it plays on), play / pause,
// scrub, set the speed and the skinning method; drag a joint (IK) or, in
// edit mode, a vertex (Laplacian editing); blend clips of the skeleton; play a
// clip on a character (every mesh of a skeleton); retarget a clip onto the
// character and play it there; drop a file to import it.
import * as api from './api.js';
import { BlendCharacter } from './blend/blend_character.js';
import { BlendPanel } from './blend/blend_panel.js';
import { IkDrag } from './drags/ik_drag.js';
import { VertexDrag } from './drags/vertex_drag.js';
import { DropImport } from './drop_import.js';
import { CharacterPlayer, charactersOf, clipsForCharacter } from './playback/character_player.js';
import { MeshPlayer, SKINNING_METHODS, clipsFor } from './playback/mesh_player.js';
import { Player } from './playback/player.js';
import { RetargetPanel } from './retarget/retarget_panel.js';
import { CharacterView } from './views/character_view.js';
import { JointTree } from './views/joint_tree.js';
import { MeshView } from './views/mesh_view.js';
import { SkeletonView } from './views/skeleton_view.js';

const $ = (id) => document.getElementById(id);
const ui = {
  character: $('character'), mesh: $('mesh'), clip: $('clip'), play: $('play'), scrub: $('scrub'), speed: $('speed'),
  meshControls: $('mesh-controls'), method: $('method'), showSkeleton: $('show-skeleton'),
  skeletonToggle: $('skeleton-toggle'), edit: $('edit'),
  editControls: $('edit-controls'), deformMethod: $('deform-method'), deformWeights: $('deform-weights'),
  radius: $('radius'), reset: $('reset'), hint: $('hint'), blend: $('blend'),
  time: $('time'), frameTime: $('frame-time'), joints: $('joints'), vertices: $('vertices'), rate: $('rate'),
  message: $('message'), importProgress: $('import-progress'), importLabel: $('import-label'),
};
const HINTS = {
  skeleton: 'Drag a joint to pose it (IK)',
  mesh: 'Edit mesh to drag its vertices',
  edit: 'Drag a vertex to deform the mesh',
  blend: 'Blend: set layers, play or crossfade',
};

const view = new SkeletonView($('viewport'));
const meshView = new MeshView(view);
const player = new Player({ fps: 30 });          // the skeleton (alone, or over the mesh)
const meshPlayer = new MeshPlayer({ fps: 30 });  // the chosen mesh
const ik = new IkDrag(view, player);
const jointTree = new JointTree($('joint-tree'), view, (event) => ik.pick(event));
const vertexDrag = new VertexDrag(view, meshView);
const characterView = new CharacterView(view);
const characterPlayer = new CharacterPlayer({ fps: 30 });  // the chosen character
const dropImport = new DropImport(document.body, { progress: ui.importProgress, label: ui.importLabel });
const blend = new BlendPanel($('blend-panel'), { speed: () => Number(ui.speed.value) });
const retarget = new RetargetPanel($('retarget-panel'));
const blendCharacter = new BlendCharacter(characterView);  // the blend on the skeleton's meshes
let clips = [];
let meshes = [];
let characters = [];  // charactersOf(meshes)
let scrubbing = false;
const arrivals = [];  // stream frame arrival times, for the rate shown

const meshMode = () => ui.mesh.value !== '';
const characterMode = () => ui.character.value !== '';
// What play, scrub and speed drive.
const playback = () => (characterMode() ? characterPlayer : meshMode() ? meshPlayer : player);
// The skeleton over the mesh: when it has one, a clip plays and no edit is on.
const overlay = () =>
  ui.showSkeleton.checked && !vertexDrag.editing && Boolean(meshPlayer.mesh?.skeleton && meshPlayer.clip);

function showMessage(text) {
  ui.message.textContent = text ?? '';
}

function showClip(clip) {
  ui.scrub.max = String(clip.duration);
  ui.scrub.step = String(clip.frameTime > 0 ? clip.frameTime / 4 : clip.duration / 1000);
  ui.frameTime.textContent =
    clip.frameTime > 0 ? `frame time ${(clip.frameTime * 1000).toFixed(1)} ms` : 'key-framed';
}

// A mesh's or a character's clip, or that it is shown at rest (no clip).
function showClipOrRest(clip) {
  if (clip) {
    showClip(clip);
  } else {
    ui.time.textContent = 'at rest';
    ui.frameTime.textContent = '–';
  }
}

function showTime(time, clip, frame, unit) {
  const frameIndex = clip.frameTime > 0 ? Math.round(time / clip.frameTime) : null;
  ui.time.textContent =
    `t = ${time.toFixed(3)} / ${clip.duration.toFixed(3)} s` + (frameIndex !== null ? ` · frame ${frameIndex}` : '');
  if (!scrubbing) ui.scrub.value = String(time);
  if (frame) showRate(unit);
}

// Counts a frame's arrival and shows the rate over the last second.
function showRate(unit) {
  const now = performance.now();
  arrivals.push(now);
  while (arrivals.length && now - arrivals[0] > 1000) arrivals.shift();
  ui.rate.textContent = `${arrivals.length} ${unit}/s`;
}

function showState(playing) {
  ui.play.textContent = playing ? 'Pause' : 'Play';
  if (!playing) ui.rate.textContent = '';
  arrivals.length = 0;
}

// Which controls apply now (mode, mesh, clip, editing), and whether the skeleton shows.
function updateControls() {
  const editing = vertexDrag.editing;
  const mesh = meshMode() ? meshPlayer.mesh : null;
  const clip = characterMode() ? characterPlayer.clip : meshMode() ? meshPlayer.clip : player.clip;
  ui.meshControls.hidden = !meshMode();
  ui.editControls.hidden = !editing;
  ui.edit.checked = editing;
  const blending = blend.enabled;
  ui.play.disabled = ui.scrub.disabled = editing || blending || !clip;
  ui.clip.disabled = editing || !ui.clip.value;
  ui.mesh.disabled = blending;
  ui.method.disabled = editing || !clip || !mesh?.skeleton;
  ui.skeletonToggle.hidden = !mesh?.skeleton;
  // Blending needs a skeleton with a clip (a mesh's, shown alone while blending).
  ui.blend.disabled = editing || !clip || (meshMode() && !mesh?.skeleton);
  ui.character.disabled = blending;
  ui.hint.textContent = editing ? HINTS.edit : blending ? HINTS.blend : meshMode() ? HINTS.mesh : HINTS.skeleton;
  view.figure.visible = !characterMode() && (!meshMode() || overlay());
  $('joint-tree').hidden = !view.figure.visible || !view.skeleton;
  if ($('joint-tree').hidden) jointTree.setHovered(-1);
}

player.addEventListener('load', ({ detail: { clip, skeleton } }) => {
  view.setSkeleton(skeleton);
  jointTree.setSkeleton(skeleton);
  ui.joints.textContent = `${skeleton.joints.length} joints`;
  if (!meshMode() && !characterMode()) showClip(clip);
  if (blend.enabled) {
    blend.setCharacter(skeleton, clipsOf(skeleton), clip.name);
    showBlendBody(skeleton).catch(failed('Blend: '));
  }
  updateControls();
});
player.addEventListener('pose', ({ detail: { time, pose, frame } }) => {
  if (blend.enabled) return;  // the blend draws the skeleton
  view.setPose(pose);
  if (!meshMode() && !characterMode()) showTime(time, player.clip, frame, 'poses');
});
player.addEventListener('state', ({ detail: { playing } }) => !meshMode() && !characterMode() && showState(playing));
player.addEventListener('error', ({ detail }) => showMessage(detail));

meshPlayer.addEventListener('load', ({ detail: { mesh, geometry, clip } }) => {
  if (meshView.geometry !== geometry) {
    meshView.show(geometry);
    // A clip places the mesh (a walk's root sits at hip height, not at the
    // bind pose's origin): frame its first skinned frame instead.
    if (!clip) meshView.frame();
  }
  ui.vertices.textContent = `${mesh.vertexCount} vertices · ${mesh.triangleCount} triangles`;
  if (!(mesh.skeleton && clip))
    ui.joints.textContent = mesh.targetNames?.length ? `${mesh.targetNames.length} morph targets` : '';
  showClipOrRest(clip);
  updateControls();
});
meshPlayer.addEventListener('frame', ({ detail: { time, positions, normals, frame } }) => {
  if (vertexDrag.editing) return;
  meshView.setPositions(positions, normals);
  if (!meshView.lastCenter) meshView.frame();
  meshView.follow();
  showTime(time, meshPlayer.clip, frame, 'frames');
  if (overlay()) player.seek(time);
});
meshPlayer.addEventListener('state', ({ detail: { playing } }) => meshMode() && showState(playing));
meshPlayer.addEventListener('error', ({ detail }) => showMessage(detail));

characterPlayer.addEventListener('load', ({ detail: { character, geometries, clip } }) => {
  if (characterView.parts[0]?.geometry !== geometries[0]) {
    characterView.show(geometries);
    if (!clip) characterView.frame();  // else its first skinned frame is framed
  }
  const triangles = character.meshes.reduce((n, m) => n + m.triangleCount, 0);
  ui.vertices.textContent =
    `${plural(character.meshes.length, 'mesh', 'meshes')} · ${characterView.vertexCount} vertices · ${triangles} triangles`;
  ui.joints.textContent = '';
  showClipOrRest(clip);
  updateControls();
});
characterPlayer.addEventListener('frame', ({ detail: { time, meshes: skinned, frame } }) => {
  characterView.setMeshes(skinned);
  if (!characterView.lastCenter) characterView.frame();
  characterView.follow();
  showTime(time, characterPlayer.clip, frame, 'frames');
});
characterPlayer.addEventListener('state', ({ detail: { playing } }) => characterMode() && showState(playing));
characterPlayer.addEventListener('error', ({ detail }) => showMessage(detail));

let blendFailed = false;  // a blend error is on screen until a motion evaluates again
blend.addEventListener('pose', ({ detail: { time, motion, pose, frame } }) => {
  if (blendFailed) showMessage('');
  blendFailed = false;
  view.setPose(pose);
  blendCharacter.pose(motion, time);
  ui.time.textContent = `t = ${time.toFixed(3)} s · blend`;
  if (frame) showRate('poses');
});
blend.addEventListener('state', () => {
  ui.rate.textContent = '';
  arrivals.length = 0;
});
blendCharacter.addEventListener('error', ({ detail }) => showMessage(`Blend: ${detail}`));
blend.addEventListener('error', ({ detail }) => {
  blendFailed = true;
  showMessage(`Blend: ${detail}`);
});

ik.addEventListener('solve', ({ detail: { joint, response } }) => {
  const [residual] = response.residuals;
  showMessage(
    response.converged
      ? `IK: ${joint} reached (${response.iterations} iterations)`
      : `IK: ${joint} out of reach by ${residual.positionError.toFixed(2)}`,
  );
});
ik.addEventListener('error', ({ detail }) => showMessage(`IK: ${detail}`));

vertexDrag.addEventListener('deform', ({ detail: { response, ms, regionSize } }) => {
  meshView.setPositions(response.positions);
  ui.rate.textContent = `deform ${ms.toFixed(1)} ms`;
  const handles = vertexDrag.handles.size;
  showMessage(`Deform: ${handles} handle${handles === 1 ? '' : 's'}, ${regionSize} vertices in the region` +
              (response.iterations ? `, ${response.iterations} ARAP iterations` : ''));
});
vertexDrag.addEventListener('error', ({ detail }) => showMessage(`Deform: ${detail}`));

// Fills the clip picker with `list`, keeping `wanted` (or the current
// choice) when it is there; an empty list offers the rest shape only.
function fillClips(list, wanted) {
  const current = wanted ?? ui.clip.value;
  ui.clip.replaceChildren();
  for (const clip of list) ui.clip.add(new Option(`${clip.name} (${clip.duration.toFixed(2)} s)`, clip.name));
  if (list.length === 0) ui.clip.add(new Option('none (at rest)', ''));
  if (list.some((c) => c.name === current)) ui.clip.value = current;
}

// The mesh's clip on the mesh and, when the mesh is bound to the clip's
// skeleton, on the skeleton drawn over it.
async function loadMeshClip() {
  const mesh = meshes.find((m) => m.name === ui.mesh.value);
  const clip = ui.clip.value && api.getClip(ui.clip.value);
  await Promise.all([meshPlayer.load(mesh, clip), mesh.skeleton && clip ? player.load(clip) : null]);
  updateControls();
}

// Leaves character mode: the character's meshes go, its playback stops.
function leaveCharacter() {
  ui.character.value = '';
  retarget.setCharacter('');
  characterPlayer.unload();
  characterView.clear();
}

// Plays a clip of skeleton `skeleton` on all of its meshes (none: the
// skeleton alone, as chooseMesh('') shows it).
async function chooseCharacter(skeleton, wantedClip) {
  const character = characters.find((c) => c.skeleton === skeleton);
  if (!character) return chooseMesh('', wantedClip);
  setEditing(false);
  showMessage('');
  ui.mesh.value = '';
  meshPlayer.unload();
  meshView.clear();
  view.setOverlay(false);
  ui.character.value = skeleton;
  retarget.setCharacter(skeleton);
  player.pause();
  ik.enabled = false;
  view.followRoot = false;  // the camera follows the character
  ui.vertices.textContent = '';
  fillClips(await clipsForCharacter(skeleton, clips), wantedClip);
  showState(false);
  await loadCharacterClip();
}

async function loadCharacterClip() {
  const character = characters.find((c) => c.skeleton === ui.character.value);
  await characterPlayer.load(character, ui.clip.value);
  updateControls();
}

async function chooseMesh(name, wantedClip) {
  leaveCharacter();
  setEditing(false);
  showMessage('');
  ui.mesh.value = name;
  showState(false);
  const mesh = meshes.find((m) => m.name === name);
  if (!mesh) {  // none: the skeleton alone, as before
    meshPlayer.unload();
    meshView.clear();
    view.followRoot = true;
    view.setOverlay(false);
    ik.enabled = true;
    ui.vertices.textContent = '';
    fillClips(clips, wantedClip);
    updateControls();
    if (ui.clip.value) await player.load(ui.clip.value);
    return;
  }
  player.pause();
  ik.enabled = false;
  view.followRoot = false;  // the camera follows the mesh
  view.setOverlay(true);
  fillClips(clipsFor(mesh, clips), wantedClip);
  await loadMeshClip();
}

// Edit mode: playback pauses, the mesh is shown at rest and its vertices
// can be dragged; leaving it shows the clip again.
function setEditing(on) {
  if (on !== vertexDrag.editing && (!on || meshPlayer.geometry)) {
    if (on) {
      meshPlayer.pause();
      vertexDrag.start(meshPlayer.mesh.name, meshPlayer.geometry);
      meshView.showRest();
    } else {
      vertexDrag.stop();
      ui.rate.textContent = '';
      if (meshPlayer.clip) meshPlayer.refresh();
      else meshView.showRest();
    }
  }
  updateControls();
}

const clipsOf = (skeleton) => clips.filter((c) => c.skeleton === skeleton.name).map((c) => c.name);

// Blend mode: the clip's skeleton (shown alone) is driven by the blend panel;
// leaving it shows the clip again.
async function setBlending(on) {
  if (on && (meshMode() || characterMode())) await chooseMesh('', playback().clip?.name);
  if (on && player.skeleton) {
    player.pause();
    ik.enabled = false;
    blend.setCharacter(player.skeleton, clipsOf(player.skeleton), player.clip.name);
    await showBlendBody(player.skeleton);
    blend.setEnabled(true);
  } else if (!on) {
    blend.setEnabled(false);
    await blendCharacter.show(null);
    view.setOverlay(false);
    ik.enabled = !meshMode();
    showMessage('');
    if (player.clip) await player.refresh();
  }
  ui.blend.checked = blend.enabled;
  updateControls();
}

// While blending: the skeleton's meshes (its character), if it has any, under the skeleton drawn thin.
async function showBlendBody(skeleton) {
  await blendCharacter.show(characters.find((c) => c.skeleton === skeleton.name) ?? null);
  view.setOverlay(Boolean(blendCharacter.character));
  if (blend.enabled) await blend.refresh();
}

const plural = (n, one, many) => `${n} ${n === 1 ? one : many}`;
const failed = (prefix) => (error) => showMessage(`${prefix}${error.message}`);

ui.play.addEventListener('click', () => (playback().playing ? playback().pause() : playback().play()));
ui.scrub.addEventListener('pointerdown', () => (scrubbing = true));
ui.scrub.addEventListener('pointerup', () => (scrubbing = false));
ui.scrub.addEventListener('input', () => playback().seek(Number(ui.scrub.value)));
ui.speed.addEventListener('change', () => {
  player.setSpeed(Number(ui.speed.value));
  meshPlayer.setSpeed(Number(ui.speed.value));
});
ui.clip.addEventListener('change', () => {
  showMessage('');
  (characterMode() ? loadCharacterClip() : meshMode() ? loadMeshClip() : player.load(ui.clip.value)).catch(failed(''));
});
ui.character.addEventListener('change', () => chooseCharacter(ui.character.value).catch(failed('')));
ui.mesh.addEventListener('change', () => chooseMesh(ui.mesh.value).catch(failed('')));
ui.method.addEventListener('change', () => {
  meshPlayer.setMethod(ui.method.value);
  characterPlayer.method = ui.method.value;
});
ui.showSkeleton.addEventListener('change', () => {
  updateControls();
  if (overlay()) player.seek(meshPlayer.time);
});
ui.edit.addEventListener('change', () => setEditing(ui.edit.checked));
ui.blend.addEventListener('change', () => setBlending(ui.blend.checked).catch(failed('')));
ui.deformMethod.addEventListener('change', () => vertexDrag.setOptions({ method: ui.deformMethod.value }));
ui.deformWeights.addEventListener('change', () => vertexDrag.setOptions({ weights: ui.deformWeights.value }));
ui.radius.addEventListener('change', () => vertexDrag.setOptions({ radius: Number(ui.radius.value) }));
ui.reset.addEventListener('click', () => {
  vertexDrag.reset();
  meshView.showRest();
  showMessage('');
  ui.rate.textContent = '';
});

// Fills the character and mesh pickers from the server's lists, keeping the choices.
async function loadLists() {
  [clips, meshes] = await Promise.all([api.listClips(), api.listMeshes()]);
  api.forgetSkeletons();  // a skeleton imported again may have other joints
  characters = charactersOf(meshes);
  retarget.setClips(clips);
  retarget.root.hidden = characters.length === 0;
  const [character, mesh] = [ui.character.value, ui.mesh.value];
  ui.character.replaceChildren(new Option('none', ''));
  for (const c of characters)
    ui.character.add(new Option(`${c.skeleton} (${plural(c.meshes.length, 'mesh', 'meshes')})`, c.skeleton));
  ui.mesh.replaceChildren(new Option('none', ''));
  for (const m of meshes) ui.mesh.add(new Option(`${m.name} (${m.vertexCount} vertices)`, m.name));
  ui.character.value = characters.some((c) => c.skeleton === character) ? character : '';
  ui.mesh.value = meshes.some((m) => m.name === mesh) ? mesh : '';
}

// A dropped file was imported: it joins the pickers and is shown (its
// character, else its first clip on its skeleton, else its first mesh).
dropImport.addEventListener('imported', ({ detail: { asset, warnings } }) => {
  (async () => {
    await loadLists();
    const skinned = asset.meshes?.find((m) => m.skeleton);
    if (skinned) {
      if (blend.enabled) await setBlending(false);
      await chooseCharacter(skinned.skeleton, asset.clips?.[0]?.name);
    } else if (asset.clips?.length) {
      if (blend.enabled) await setBlending(false);
      await chooseMesh('', asset.clips[0].name);
    } else if (asset.meshes?.length) {
      await chooseMesh(asset.meshes[0].name);
    }
    if (warnings?.length) showMessage(`Import: ${warnings.join('; ')}`);
  })().catch(failed('Import: '));
});
// A clip retargeted onto the character: it joins the pickers and plays on it.
retarget.addEventListener('retargeted', ({ detail: { response, skeleton } }) => {
  (async () => {
    await loadLists();
    if (blend.enabled) await setBlending(false);
    await chooseCharacter(skeleton, response.clip.name);
    if (characterPlayer.clip?.name === response.clip.name) characterPlayer.play();
  })().catch(failed('Retarget: '));
});

dropImport.addEventListener('error', ({ detail }) => showMessage(`Import: ${detail}`));

// ?character=SKELETON|mesh=NAME&clip=NAME&method=LBS|DQS pick what is shown first.
async function start() {
  await loadLists();
  const params = new URLSearchParams(location.search);
  const method = params.get('method')?.toUpperCase();
  if (SKINNING_METHODS.includes(method)) {
    ui.method.value = method;
    meshPlayer.method = method;
  }
  // With nothing asked for, a skinned mesh that has a clip to play (the
  // seeded demo character) is the most telling first view.
  if (params.has('character')) {
    await chooseCharacter(params.get('character'), params.get('clip'));
    if (!characterMode()) showMessage(`No character ${params.get('character')} (a skeleton with meshes)`);
    return;
  }
  const playable = meshes.find((m) => m.skeleton && clipsFor(m, clips).length > 0);
  const wantedMesh = params.get('mesh') ?? (params.has('clip') ? null : playable?.name);
  if (wantedMesh && meshes.some((m) => m.name === wantedMesh)) {
    await chooseMesh(wantedMesh, params.get('clip'));
    return;
  }
  if (clips.length === 0) {
    showMessage(meshes.length ? 'No clips loaded: choose a mesh' : 'No clips loaded: import one (armature import file.bvh)');
    return;
  }
  await chooseMesh('', params.get('clip'));
  if (wantedMesh) showMessage(`No mesh named ${wantedMesh}`);
}

// For tests and the console.
window.armatureViewer = {
  player, view, ik, meshPlayer, meshView, vertexDrag, blend, characterPlayer, characterView, dropImport, retarget,
  jointTree, blendCharacter,
};

start().catch(failed('Cannot reach the server: '));
