// A mesh's materials as three.js's GLTFLoader builds them: MeshStandardMaterial
// from glTF PBR metallic-roughness (linear colour factors, sRGB colour maps,
// metalness and roughness from one map, normal and occlusion maps, alpha
// modes, flipY off, the samplers' filters and wraps), from GetMaterial answers
// and the images' stored bytes, which the browser decodes (the server never does).
import * as THREE from 'three';

import { getMaterial, getMaterialImage } from '../api.js';

const FILTERS = {
  9728: THREE.NearestFilter, 9729: THREE.LinearFilter, 9984: THREE.NearestMipmapNearestFilter,
  9985: THREE.LinearMipmapNearestFilter, 9986: THREE.NearestMipmapLinearFilter, 9987: THREE.LinearMipmapLinearFilter,
};
const WRAPS = { 33071: THREE.ClampToEdgeWrapping, 33648: THREE.MirroredRepeatWrapping, 10497: THREE.RepeatWrapping };

// A texture from an image's bytes ({ mimeType, data }) and a TextureRef's sampler, as GLTFLoader's.
async function makeTexture(image, sampler = {}, colorSpace = THREE.NoColorSpace) {
  const blob = new Blob([image.data], { type: image.mimeType });
  const texture = new THREE.Texture(await createImageBitmap(blob, { premultiplyAlpha: 'none' }));
  texture.flipY = false;
  texture.colorSpace = colorSpace;
  texture.magFilter = FILTERS[sampler.magFilter] ?? THREE.LinearFilter;
  texture.minFilter = FILTERS[sampler.minFilter] ?? THREE.LinearMipmapLinearFilter;
  texture.wrapS = WRAPS[sampler.wrapS] ?? THREE.RepeatWrapping;
  texture.wrapT = WRAPS[sampler.wrapT] ?? THREE.RepeatWrapping;
  texture.generateMipmaps = texture.minFilter !== THREE.NearestFilter && texture.minFilter !== THREE.LinearFilter;
  texture.needsUpdate = true;
  return texture;
}

// `material`: a GetMaterial answer (proto3 JSON); `image(i)`: its image i's
// { mimeType, data }. `hasTangents`: the geometry has TANGENT (it never does
// here), else the normal map's y flips, as GLTFLoader does.
export async function buildMaterial(material, image, hasTangents = false) {
  const params = { color: new THREE.Color(1, 1, 1), opacity: 1 };
  const f = material.baseColorFactor ?? [];
  if (f.length === 4) {
    params.color.setRGB(f[0], f[1], f[2], THREE.LinearSRGBColorSpace);
    params.opacity = f[3];
  }
  params.metalness = material.metallicFactor ?? 1;
  params.roughness = material.roughnessFactor ?? 1;
  if (material.doubleSided) params.side = THREE.DoubleSide;
  if (material.alphaMode === 'BLEND') {
    params.transparent = true;
    params.depthWrite = false;
  } else if (material.alphaMode === 'MASK') {
    params.alphaTest = material.alphaCutoff ?? 0.5;
  }
  const e = material.emissiveFactor ?? [];
  if (e.length === 3) params.emissive = new THREE.Color().setRGB(e[0], e[1], e[2], THREE.LinearSRGBColorSpace);
  const textures = new Map();  // one texture per image and colour space
  const texture = async (ref, colorSpace) => {
    if (!ref) return null;
    const key = `${ref.image}:${colorSpace}:${JSON.stringify(ref.sampler ?? {})}`;
    if (!textures.has(key)) textures.set(key, image(ref.image).then((bytes) => makeTexture(bytes, ref.sampler, colorSpace)));
    return textures.get(key);
  };
  const [map, metalRough, normal, occlusion, emissive] = await Promise.all([
    texture(material.baseColorTexture, THREE.SRGBColorSpace),
    texture(material.metallicRoughnessTexture, THREE.NoColorSpace),
    texture(material.normalTexture, THREE.NoColorSpace),
    texture(material.occlusionTexture, THREE.NoColorSpace),
    texture(material.emissiveTexture, THREE.SRGBColorSpace),
  ]);
  if (map) params.map = map;
  if (metalRough) params.metalnessMap = params.roughnessMap = metalRough;
  if (normal) {
    const s = material.normalTexture.scale ?? 1;
    params.normalMap = normal;
    params.normalScale = new THREE.Vector2(s, hasTangents ? s : -s);
  }
  if (occlusion) {
    params.aoMap = occlusion;
    params.aoMapIntensity = material.occlusionTexture.scale ?? 1;
  }
  if (emissive) params.emissiveMap = emissive;
  const built = new THREE.MeshStandardMaterial(params);
  built.name = material.name ?? '';
  return built;
}

// Every material of a GetMeshGeometry answer, built (its images fetched once each).
export async function loadMeshMaterials(geometry) {
  const images = new Map();
  return Promise.all(geometry.materials.map(async (_, m) => {
    const material = await getMaterial(geometry.mesh, m);
    const image = (i) => {
      if (!images.has(`${m}:${i}`)) images.set(`${m}:${i}`, getMaterialImage(geometry.mesh, m, i));
      return images.get(`${m}:${i}`);
    };
    return buildMaterial(material, image);
  }));
}

// A material and its maps' GPU copies (a map may serve two slots).
export function disposeMaterial(material) {
  const maps = ['map', 'metalnessMap', 'roughnessMap', 'normalMap', 'aoMap', 'emissiveMap'];
  new Set(maps.map((k) => material[k]).filter(Boolean)).forEach((t) => t.dispose());
  material.dispose();
}
