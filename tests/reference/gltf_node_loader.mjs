// Loading a glTF/GLB with three.js's GLTFLoader in node, for the reference
// scripts: buffers inlined as data: URIs (node's fetch reads those), images,
// textures and materials dropped (geometry and animation are all they need).
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';

function toJson(path) {
  const bytes = readFileSync(path);
  if (bytes.subarray(0, 4).toString('latin1') !== 'glTF') return { json: JSON.parse(bytes.toString('utf8')), bin: null };
  // GLB: a JSON chunk, then an optional BIN chunk.
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let offset = 12;
  let json = null;
  let bin = null;
  while (offset + 8 <= bytes.length) {
    const length = view.getUint32(offset, true);
    const type = view.getUint32(offset + 4, true);
    const chunk = bytes.subarray(offset + 8, offset + 8 + length);
    if (type === 0x4e4f534a) json = JSON.parse(chunk.toString('utf8'));
    else if (type === 0x004e4942) bin = Buffer.from(chunk);
    offset += 8 + length;
  }
  return { json, bin };
}

function prepare(path) {
  const { json, bin } = toJson(path);
  for (const buffer of json.buffers || []) {
    if (buffer.uri === undefined) {
      buffer.uri = 'data:application/octet-stream;base64,' + bin.toString('base64');
    } else if (!buffer.uri.startsWith('data:')) {
      const data = readFileSync(join(dirname(path), decodeURIComponent(buffer.uri)));
      buffer.uri = 'data:application/octet-stream;base64,' + data.toString('base64');
    }
  }
  delete json.images;
  delete json.textures;
  delete json.samplers;
  delete json.materials;
  for (const mesh of json.meshes || []) for (const p of mesh.primitives) delete p.material;
  return JSON.stringify(json);
}

// three's FileLoader reports progress with the browser's ProgressEvent, which
// node lacks; data: URIs are fetched through it.
globalThis.ProgressEvent ??= class ProgressEvent extends Event {
  constructor(type, init = {}) {
    super(type);
    Object.assign(this, init);
  }
};

// The parsed glTF (GLTFLoader's result: scene, animations, parser).
export function loadGltf(path) {
  return new Promise((resolve, reject) => new GLTFLoader().parse(prepare(path), '', resolve, reject));
}
