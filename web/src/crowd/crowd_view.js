// A crowd drawn instanced: one instance per character of one geometry holding
// every bone of the skeleton (a tetrahedron from a joint's parent to the
// joint), skinned in the vertex shader from a float texture of bone matrices
// (a row per character, three texels per bone): 1,000 characters are one draw
// call of 1,000 instances, cheap for software GL too, which pays per instance.
// Each character gets its clip's colour. Orbit camera and a grid sized to the crowd.
import * as THREE from 'three';

import { resizeStage, setUpStage } from '../views/stage.js';

const UP = new THREE.Vector3(0, 1, 0);

// Every bone's tetrahedron, from a triangle around y = 0 to a tip at y = 1, with its bone's index per vertex.
function skeletonGeometry(bones) {
  const r = 0.5, c = Math.cos((2 * Math.PI) / 3) * r, s = Math.sin((2 * Math.PI) / 3) * r;
  const corners = [[r, 0, 0], [c, 0, s], [c, 0, -s], [0, 1, 0]];
  const faces = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]];
  const positions = [], normals = [], boneIndex = [];
  for (let b = 0; b < bones; ++b) {
    for (const face of faces) {  // flat faces: each its own vertices and normal
      const [p, q, t] = face.map((i) => new THREE.Vector3(...corners[i]));
      const n = new THREE.Vector3().subVectors(q, p).cross(new THREE.Vector3().subVectors(t, p)).normalize();
      for (const v of [p, q, t]) {
        positions.push(v.x, v.y, v.z);
        normals.push(n.x, n.y, n.z);
        boneIndex.push(b);
      }
    }
  }
  const geometry = new THREE.InstancedBufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  geometry.setAttribute('normal', new THREE.Float32BufferAttribute(normals, 3));
  geometry.setAttribute('boneIndex', new THREE.Float32BufferAttribute(boneIndex, 1));
  return geometry;
}

// Lambert shading with each vertex placed by its bone's matrix for the instance (texels 3b..3b+2 of row gl_InstanceID).
function skinnedLambert(boneTexture) {
  const material = new THREE.MeshLambertMaterial({ vertexColors: true });
  material.onBeforeCompile = (shader) => {
    shader.uniforms.boneTexture = { value: boneTexture };
    shader.vertexShader = shader.vertexShader
      .replace('#include <common>', `#include <common>
        attribute float boneIndex;
        uniform highp sampler2D boneTexture;`)
      .replace('#include <beginnormal_vertex>', `
        int texel = int(boneIndex) * 3;
        mat4 boneMatrix = transpose(mat4(texelFetch(boneTexture, ivec2(texel, gl_InstanceID), 0),
                                         texelFetch(boneTexture, ivec2(texel + 1, gl_InstanceID), 0),
                                         texelFetch(boneTexture, ivec2(texel + 2, gl_InstanceID), 0),
                                         vec4(0.0, 0.0, 0.0, 1.0)));
        vec3 objectNormal = normalize(transpose(inverse(mat3(boneMatrix))) * normal);`)
      .replace('#include <begin_vertex>', 'vec3 transformed = (boneMatrix * vec4(position, 1.0)).xyz;');
  };
  return material;
}

export class CrowdView {
  // `parents` of the skeleton's joints, `count` characters; `colourOf(c)` a character's colour (a THREE.Color);
  // `shown(parent, joint)`: whether that bone is drawn.
  constructor(container, parents, count, colourOf, shown = () => true) {
    setUpStage(this, container, { antialias: false, near: 0.01 });
    this.joints = parents.length;
    this.bones = [];  // [parent, joint]
    parents.forEach((p, k) => p >= 0 && shown(p, k) && this.bones.push([p, k]));
    this.count = count;
    this.matrices = new Float32Array(this.bones.length * 3 * 4 * count);
    this.boneTexture = new THREE.DataTexture(this.matrices, this.bones.length * 3, count, THREE.RGBAFormat,
                                             THREE.FloatType);
    const geometry = skeletonGeometry(this.bones.length);
    geometry.instanceCount = count;
    const colours = new Float32Array(count * 3);
    for (let c = 0; c < count; ++c) colourOf(c).toArray(colours, c * 3);
    geometry.setAttribute('color', new THREE.InstancedBufferAttribute(colours, 3));
    this.mesh = new THREE.Mesh(geometry, skinnedLambert(this.boneTexture));
    this.mesh.frustumCulled = false;  // the bones move in the shader: the geometry's bounds say nothing
    this.scene.add(this.mesh);
    this.thickness = 0.02;
    this.scratch = { m: new THREE.Matrix4(), q: new THREE.Quaternion(), s: new THREE.Vector3(), a: new THREE.Vector3(),
                     d: new THREE.Vector3() };
    this.resize();
  }

  // Instances drawn: one per character.
  get instances() {
    return this.mesh.geometry.instanceCount;
  }

  resize() {
    resizeStage(this);
  }

  // The crowd spans `width` × `depth` around the origin and a character is `height` tall.
  frame(width, depth, height) {
    this.thickness = height * 0.04;
    this.scene.add(new THREE.GridHelper(Math.max(width, depth) * 1.1, 40, 0x4a5260, 0x30353d));
    const reach = Math.max(width, depth);
    this.camera.position.set(0, reach * 0.45, reach * 0.75);
    this.controls.target.set(0, height * 0.5, reach * 0.05);
    this.controls.update();
  }

  // Every character's world joint positions (count × joints × 3) as its bones' matrices; then renders.
  draw(positions) {
    const { m, q, s, a, d } = this.scratch;
    const j = this.joints, nb = this.bones.length, out = this.matrices, e = m.elements;
    for (let c = 0; c < this.count; ++c) {
      const o = c * j * 3;
      for (let b = 0; b < nb; ++b) {
        const [p, k] = this.bones[b];
        a.set(positions[o + p * 3], positions[o + p * 3 + 1], positions[o + p * 3 + 2]);
        d.set(positions[o + k * 3] - a.x, positions[o + k * 3 + 1] - a.y, positions[o + k * 3 + 2] - a.z);
        const length = d.length();
        if (length > 1e-9) q.setFromUnitVectors(UP, d.divideScalar(length));
        else q.identity();
        m.compose(a, q, s.set(this.thickness, length, this.thickness));
        const at = (c * nb + b) * 12;  // three rows of the column-major matrix
        for (let row = 0; row < 3; ++row) {
          out[at + row * 4] = e[row];
          out[at + row * 4 + 1] = e[4 + row];
          out[at + row * 4 + 2] = e[8 + row];
          out[at + row * 4 + 3] = e[12 + row];
        }
      }
    }
    this.boneTexture.needsUpdate = true;
    this.renderer.render(this.scene, this.camera);
  }
}
