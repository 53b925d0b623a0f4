// A mesh drawn in the SkeletonView's scene: the rest geometry from
// GetMeshGeometry (triangles, bind-space positions and normals, UVs), drawn
// with the file's materials once they load (flat until then, or without), then any
// positions the server sends (skinned frames, deformed shapes) written into
// the same buffers. Normals follow the server's when it sends them, else they
// are recomputed from the triangles.
import * as THREE from 'three';

import { disposeMaterial, loadMeshMaterials } from './gltf_material.js';

export const MESH_COLOR = 0x8fb3d9;

// Points `view`'s camera at `box`, over a grid three times its size: big
// enough to stand on, small enough that the camera (two sizes away) is off it
// (software WebGL drops grid lines that pass behind the camera), and a hair
// below the box so a flat mesh lying on it does not flicker through it.
export function frameOnGrid(view, box) {
  const span = Math.max(...box.getSize(new THREE.Vector3()).toArray(), 1e-3);
  view.setGrid(span / 4);
  view.frameBox(box);
  view.grid.position.y -= span * 1e-3;
}

// Moves `view`'s camera (and its grid) by the ground shift from `from` to `to`.
export function panAcross(view, from, to) {
  view.panAlongGround(to.clone().sub(from));
}

export class MeshView {
  // `view`: the SkeletonView whose scene, camera and renderer are used;
  // `color`: the material's (a character's meshes each get their own).
  constructor(view, { color = MESH_COLOR } = {}) {
    this.view = view;
    this.color = color;
    this.geometry = null;  // the GetMeshGeometry response
    this.object = null;    // the THREE.Mesh
    this.lastCenter = null;
  }

  get vertexCount() {
    return this.geometry?.vertexCount ?? 0;
  }

  // Shows `geometry` (a GetMeshGeometry response) at rest, replacing any mesh.
  show(geometry) {
    this.clear();
    this.geometry = geometry;
    const buffer = new THREE.BufferGeometry();
    buffer.setAttribute('position', new THREE.BufferAttribute(new Float32Array(geometry.positions), 3));
    if (geometry.normals?.length === geometry.positions.length)
      buffer.setAttribute('normal', new THREE.BufferAttribute(new Float32Array(geometry.normals), 3));
    if (geometry.triangles?.length) buffer.setIndex(geometry.triangles);
    if (!buffer.getAttribute('normal')) buffer.computeVertexNormals();
    if (geometry.uvs?.length === 2 * geometry.vertexCount)
      buffer.setAttribute('uv', new THREE.BufferAttribute(new Float32Array(geometry.uvs), 2));
    buffer.computeBoundingSphere();
    const material = new THREE.MeshStandardMaterial({
      color: this.color, roughness: 0.55, metalness: 0.05, side: THREE.DoubleSide,
    });
    this.object = new THREE.Mesh(buffer, material);
    this.view.scene.add(this.object);
    // Flat until the file's own materials (and their images) arrive.
    this.materialsReady = this.useFileMaterials(geometry);
  }

  // Draws the mesh with its file's materials, one per material group (a
  // group without one keeps the flat colour). Resolves true once they show.
  async useFileMaterials(geometry) {
    if (!geometry.materials?.length || !geometry.materialGroups?.length) return false;
    let built;
    try {
      built = await loadMeshMaterials(geometry);
    } catch (e) {
      console.warn(`mesh ${geometry.mesh}: its materials could not be loaded (${e.message}); drawn flat`);
      return false;
    }
    if (this.geometry !== geometry) {  // another mesh was shown meanwhile
      built.forEach(disposeMaterial);
      return false;
    }
    const buffer = this.object.geometry;
    const flat = this.object.material;
    for (const g of geometry.materialGroups)
      buffer.addGroup(3 * g.firstTriangle, 3 * g.triangleCount, g.material >= 0 ? g.material : built.length);
    this.object.material = [...built, flat];
    return true;
  }

  // Writes new positions (x, y, z per vertex) and, if given, normals.
  setPositions(positions, normals = null) {
    if (!this.object || positions.length !== 3 * this.vertexCount) return;
    const buffer = this.object.geometry;
    buffer.getAttribute('position').array.set(positions);
    buffer.getAttribute('position').needsUpdate = true;
    if (normals?.length === positions.length) {
      buffer.getAttribute('normal').array.set(normals);
      buffer.getAttribute('normal').needsUpdate = true;
    } else {
      buffer.computeVertexNormals();
    }
    buffer.computeBoundingSphere();
    buffer.computeBoundingBox();
  }

  // Back to the rest shape.
  showRest() {
    if (this.geometry) this.setPositions(this.geometry.positions, this.geometry.normals);
  }

  // The mean of the vertices as drawn now.
  centroid() {
    const p = this.object.geometry.getAttribute('position').array;
    const c = new THREE.Vector3();
    for (let i = 0; i < p.length; i += 3) c.set(c.x + p[i], c.y + p[i + 1], c.z + p[i + 2]);
    return c.divideScalar(Math.max(p.length / 3, 1));
  }

  // Keeps a mesh that walks in view: the camera moves with its centroid's
  // shift across the ground (the centroid, not the bounds: swinging limbs
  // barely move it).
  follow() {
    if (!this.object) return;
    const center = this.centroid();
    if (this.lastCenter) panAcross(this.view, this.lastCenter, center);
    this.lastCenter = center;
  }

  // Current position of vertex `index` (world space: the mesh is not transformed).
  vertexPosition(index) {
    return new THREE.Vector3().fromBufferAttribute(this.object.geometry.getAttribute('position'), index);
  }

  // Points the camera at the mesh's bounds (frameOnGrid).
  frame() {
    if (!this.object) return;
    frameOnGrid(this.view, new THREE.Box3().setFromObject(this.object));
    this.lastCenter = this.centroid();
  }

  // The length of the rest shape's bounding box diagonal.
  size() {
    if (!this.geometry) return 0;
    return new THREE.Box3().setFromArray(this.geometry.positions).getSize(new THREE.Vector3()).length();
  }

  clear() {
    if (!this.object) return;
    this.view.scene.remove(this.object);
    this.object.geometry.dispose();
    [this.object.material].flat().forEach(disposeMaterial);
    this.object = null;
    this.geometry = null;
    this.lastCenter = null;
  }
}
