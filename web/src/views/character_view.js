// A character drawn in the SkeletonView's scene: one MeshView per mesh, each
// in its own shade, written from one SkinCharacter answer at a time. The
// camera frames the bounds of all of them and follows their common centroid.
import * as THREE from 'three';
import { MeshView, frameOnGrid, panAcross } from './mesh_view.js';

// Distinct, muted shades: neighbouring parts (head, torso, hands) stay apart.
const PALETTE = [0x5b9bd5, 0xe07b53, 0x6cc070, 0xe0c048, 0x9b6fd6, 0x4fc6b8, 0xd66f9b, 0x7f8fe0];

export class CharacterView {
  constructor(view) {
    this.view = view;
    this.parts = [];  // MeshViews, in the character's mesh order
    this.lastCenter = null;
  }

  get vertexCount() {
    return this.parts.reduce((n, part) => n + part.vertexCount, 0);
  }

  // Shows `geometries` (GetMeshGeometry answers) at rest, replacing any character.
  show(geometries) {
    this.clear();
    this.parts = geometries.map((geometry, i) => {
      const part = new MeshView(this.view, { color: PALETTE[i % PALETTE.length] });
      part.show(geometry);
      return part;
    });
  }

  // Writes one SkinCharacter answer's meshes (matched by name) into the parts.
  setMeshes(meshes) {
    const byName = new Map(meshes.map((m) => [m.mesh, m]));
    for (const part of this.parts) {
      const skinned = byName.get(part.geometry.mesh);
      if (skinned) part.setPositions(skinned.positions, skinned.normals);
    }
  }

  // The meshes drawn now (for tests: names and vertex counts).
  drawn() {
    return this.parts.filter((p) => p.object?.visible).map((p) => ({ mesh: p.geometry.mesh, vertices: p.vertexCount }));
  }

  box() {
    const box = new THREE.Box3();
    for (const part of this.parts) if (part.object) box.expandByObject(part.object);
    return box;
  }

  // The mean of every vertex of every part, as drawn now.
  centroid() {
    const sum = new THREE.Vector3();
    let n = 0;
    for (const part of this.parts) {
      sum.addScaledVector(part.centroid(), part.vertexCount);
      n += part.vertexCount;
    }
    return sum.divideScalar(Math.max(n, 1));
  }

  // Points the camera at the whole character.
  frame() {
    if (this.parts.length === 0) return;
    frameOnGrid(this.view, this.box());
    this.lastCenter = this.centroid();
  }

  // Keeps a character that runs in view (as MeshView.follow).
  follow() {
    if (this.parts.length === 0) return;
    const center = this.centroid();
    if (this.lastCenter) panAcross(this.view, this.lastCenter, center);
    this.lastCenter = center;
  }

  clear() {
    for (const part of this.parts) part.clear();
    this.parts = [];
    this.lastCenter = null;
  }
}
