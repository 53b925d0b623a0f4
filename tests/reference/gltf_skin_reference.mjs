// Independent reference for glTF skinning and morphing: three.js loads the
// file (GLTFLoader.parse, images stripped), plays one animation with an
// AnimationMixer and reports every mesh's world-space vertex positions
// (SkinnedMesh/Mesh.getVertexPosition, then the object's world matrix) and
// normals (three's shader formula: morphed normal, blended bone matrices,
// normal matrix), so the engine's skinning can be compared against it.
//
//   node gltf_skin_reference.mjs <file.gltf|file.glb> <animation index|-1> <t1,t2,...>
//
// Prints JSON: {"meshes":[{"mesh":i,"name":…,"frames":[{"time":t,"positions":[…],"normals":[…]}]}]}
// Primitives of one glTF mesh are concatenated in primitive order.
import { AnimationMixer, LoopOnce, Matrix3, Matrix4, Vector3, Vector4 } from 'three';
import { loadGltf } from './gltf_node_loader.mjs';

const [file, animationArg, timesArg] = process.argv.slice(2);
const gltf = await loadGltf(file);
const animationIndex = Number(animationArg ?? -1);
const times = (timesArg ?? '0').split(',').map(Number);

// The engine normalizes skin weights that do not sum to 1 (cesium_man has
// such vertices); three.js does the same on request.
gltf.scene.traverse((object) => {
  if (object.isSkinnedMesh) object.normalizeSkinWeights();
});

// glTF requires unit rotation keys, but some files store them rounded (e.g.
// simple_skin's 0.383, 0.924); the engine normalizes them on import, three.js
// would build a scaled matrix from them. Normalize LINEAR/STEP keys here too
// (CUBICSPLINE tracks interleave tangents and are normalized after interpolation).
for (const clip of gltf.animations) {
  for (const track of clip.tracks) {
    if (!track.name.endsWith('.quaternion') || track.createInterpolant.isInterpolantFactoryMethodGLTFCubicSpline) continue;
    const v = track.values;
    for (let i = 0; i < v.length; i += 4) {
      const len = Math.hypot(v[i], v[i + 1], v[i + 2], v[i + 3]);
      for (let c = 0; c < 4; c++) v[i + c] /= len;
    }
  }
}

const mixer = new AnimationMixer(gltf.scene);
if (animationIndex >= 0) {
  const action = mixer.clipAction(gltf.animations[animationIndex]);
  action.setLoop(LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
}

// glTF mesh index → its three.js objects (one per primitive), first instance only.
const objects = new Map();
gltf.scene.traverse((object) => {
  const a = gltf.parser.associations.get(object);
  if (!object.isMesh || a === undefined || a.meshes === undefined) return;
  if (!objects.has(a.meshes)) objects.set(a.meshes, []);
  const list = objects.get(a.meshes);
  if (!list.some((o) => o.primitive === a.primitives)) list.push({ primitive: a.primitives, object });
});

function skinnedNormal(object, index, normalMatrix) {
  const geometry = object.geometry;
  const n = new Vector3().fromBufferAttribute(geometry.attributes.normal, index);
  const morphs = geometry.morphAttributes.normal;
  if (morphs && object.morphTargetInfluences) {
    const base = n.clone();
    for (let t = 0; t < morphs.length; t++) {
      const w = object.morphTargetInfluences[t];
      if (w !== 0) n.addScaledVector(new Vector3().fromBufferAttribute(morphs[t], index), w);
    }
    if (!geometry.morphTargetsRelative) n.sub(base);
  }
  if (object.isSkinnedMesh) {
    const skinIndex = new Vector4().fromBufferAttribute(geometry.attributes.skinIndex, index);
    const skinWeight = new Vector4().fromBufferAttribute(geometry.attributes.skinWeight, index);
    const blended = new Matrix4().makeScale(0, 0, 0);
    blended.elements[15] = 0;
    const m = new Matrix4();
    for (let k = 0; k < 4; k++) {
      const w = skinWeight.getComponent(k);
      if (w === 0) continue;
      const b = skinIndex.getComponent(k);
      m.multiplyMatrices(object.skeleton.bones[b].matrixWorld, object.skeleton.boneInverses[b]);
      for (let e = 0; e < 16; e++) blended.elements[e] += w * m.elements[e];
    }
    m.multiplyMatrices(object.bindMatrixInverse, blended).multiply(object.bindMatrix);
    n.transformDirection(m);  // applies the 3×3 part and normalizes
  }
  return n.applyMatrix3(normalMatrix).normalize();
}

const out = { meshes: [] };
const frames = new Map();
for (const t of times) {
  mixer.setTime(t);
  gltf.scene.updateMatrixWorld(true);
  for (const [mesh, list] of objects) {
    if (!frames.has(mesh)) frames.set(mesh, []);
    const positions = [];
    const normals = [];
    list.sort((a, b) => a.primitive - b.primitive);
    for (const { object } of list) {
      if (object.isSkinnedMesh) object.skeleton.update();
      const normalMatrix = new Matrix3().getNormalMatrix(object.matrixWorld);
      const count = object.geometry.attributes.position.count;
      const v = new Vector3();
      for (let i = 0; i < count; i++) {
        object.getVertexPosition(i, v);
        v.applyMatrix4(object.matrixWorld);
        positions.push(v.x, v.y, v.z);
        if (object.geometry.attributes.normal) {
          const n = skinnedNormal(object, i, normalMatrix);
          normals.push(n.x, n.y, n.z);
        }
      }
    }
    frames.get(mesh).push({ time: t, positions, normals });
  }
}
for (const [mesh, list] of [...frames.entries()].sort((a, b) => a[0] - b[0])) {
  out.meshes.push({ mesh, name: gltf.parser.json.meshes[mesh].name ?? null, frames: list });
}
process.stdout.write(JSON.stringify(out));
