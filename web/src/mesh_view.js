// A mesh drawn in the SkeletonView's scene: the rest geometry from
// GetMeshGeometry (triangles, bind-space positions and normals), then any
// positions the server sends (skinned frames, deformed shapes) written into
// the same buffers. Normals follow the server's when it sends them, else they
// are recomputed from the triangles.
import * as THREE from 'three';

export const MESH_COLOR = 0x8fb3d9;

export class MeshView {
  // `view`: the SkeletonView whose scene, camera and renderer are used.
  constructor(view) {
    this.view = view;
    this.geometry = null;  // the GetMeshGeometry response
    this.object = null;    // the THREE.Mesh
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
    buffer.computeBoundingSphere();
    const material = new THREE.MeshStandardMaterial({
      color: MESH_COLOR, roughness: 0.55, metalness: 0.05, side: THREE.DoubleSide,
    });
    this.object = new THREE.Mesh(buffer, material);
    this.view.scene.add(this.object);
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

  // Current position of vertex `index` (world space: the mesh is not transformed).
  vertexPosition(index) {
    return new THREE.Vector3().fromBufferAttribute(this.object.geometry.getAttribute('position'), index);
  }

  // Points the camera at the mesh's bounds.
  frame() {
    if (!this.object) return;
    const box = new THREE.Box3().setFromObject(this.object);
    this.view.frameBox(box);
  }

  clear() {
    if (!this.object) return;
    this.view.scene.remove(this.object);
    this.object.geometry.dispose();
    this.object.material.dispose();
    this.object = null;
    this.geometry = null;
  }
}
