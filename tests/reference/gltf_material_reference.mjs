// Independent reference for materials, UVs and images: three.js's GLTFLoader
// reads a glTF/GLB and reports, per mesh, the material it built (factors,
// which maps it found, their samplers), the mesh's UVs and the bytes of each
// map's image, as GLTFLoader resolved them from the file.
//
//   node gltf_material_reference.mjs <file.glb|file.gltf>
//
// Node has no image decoder: a GLTFLoader plugin gives the parser a texture
// loader that fetches the image's URL (the data: or blob: URL GLTFLoader made
// from the file) and keeps the bytes, undecoded, as the texture's image.
// Prints JSON: {"meshes": [{"name", "vertices", "uvs": {"count", "sum", "first"},
// "material": {"name", "color", "opacity", "metalness", "roughness", "emissive",
// "side", "maps": {"map": {"bytes", "sha256", "flipY", "wrapS", "wrapT", "magFilter", "minFilter", "colorSpace"}, ...}}}]}
import { createHash } from 'node:crypto';
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { Texture } from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';

// GLTFLoader reaches URL through the browser's `self`.
globalThis.self ??= globalThis;
globalThis.ProgressEvent ??= class ProgressEvent extends Event {
  constructor(type, init = {}) {
    super(type);
    Object.assign(this, init);
  }
};

// The image's bytes as a texture image: { bytes: Uint8Array }.
class UndecodedImageLoader {
  setCrossOrigin() { return this; }
  setWithCredentials() { return this; }
  setRequestHeader() { return this; }
  load(url, onLoad, _progress, onError) {
    fetch(url).then((r) => r.arrayBuffer()).then((buffer) => {
      const texture = new Texture({ bytes: new Uint8Array(buffer), width: 1, height: 1 });
      onLoad(texture);
    }, onError);
  }
}

// A .gltf's external buffers and images inlined as data: URIs (node's fetch reads those).
function inline(path) {
  const bytes = readFileSync(path);
  if (bytes.subarray(0, 4).toString('latin1') === 'glTF') return bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const json = JSON.parse(bytes.toString('utf8'));
  for (const item of [...(json.buffers || []), ...(json.images || [])]) {
    if (item.uri === undefined || item.uri.startsWith('data:')) continue;
    const data = readFileSync(join(dirname(path), decodeURIComponent(item.uri)));
    item.uri = `data:${item.mimeType ?? 'application/octet-stream'};base64,${data.toString('base64')}`;
  }
  return JSON.stringify(json);
}

const MAPS = ['map', 'metalnessMap', 'roughnessMap', 'normalMap', 'aoMap', 'emissiveMap'];

function describeMap(texture) {
  const bytes = texture.image.bytes;
  return {
    bytes: bytes.length, sha256: createHash('sha256').update(bytes).digest('hex'), flipY: texture.flipY,
    wrapS: texture.wrapS, wrapT: texture.wrapT, magFilter: texture.magFilter, minFilter: texture.minFilter,
    colorSpace: texture.colorSpace,
  };
}

function describe(mesh) {
  const m = mesh.material;
  const maps = {};
  for (const key of MAPS) if (m[key]) maps[key] = describeMap(m[key]);
  const uv = mesh.geometry.getAttribute('uv');
  let sum = 0;
  if (uv) for (let i = 0; i < uv.count; ++i) sum += uv.getX(i) + uv.getY(i);
  return {
    name: mesh.name, vertices: mesh.geometry.getAttribute('position').count,
    uvs: uv ? { count: uv.count, sum, first: [uv.getX(0), uv.getY(0)] } : null,
    material: {
      name: m.name, color: m.color.toArray(), opacity: m.opacity, metalness: m.metalness, roughness: m.roughness,
      emissive: m.emissive.toArray(), side: m.side, maps,
    },
  };
}

const [file] = process.argv.slice(2);
const loader = new GLTFLoader();
loader.register((parser) => {
  parser.textureLoader = new UndecodedImageLoader();
  return { name: 'undecoded_images' };
});
const gltf = await new Promise((resolve, reject) => loader.parse(inline(file), '', resolve, reject));
const meshes = [];
gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(describe(o)); });
process.stdout.write(JSON.stringify({ meshes }));
