// The project's own demo character: a stylised body around the demo walk's
// skeleton, skinned and animated, as a binary glTF file (no third-party
// data), so a fresh install has a mesh to play as well as a clip.
#pragma once

#include <string>

#include "armature/base/status.h"

namespace armature {

// glTF names inside the file (the importer prefixes them with the asset name:
// asset "demo_character" gives mesh "demo_character.body" and clip
// "demo_character.walk").
inline constexpr const char* kDemoCharacterMeshName = "body";
inline constexpr const char* kDemoCharacterAnimationName = "walk";
// Posed at the skeleton's rest, no surface point is further than this from
// a bone (a segment from a joint to a child or End Site), in centimetres.
inline constexpr double kDemoCharacterMaxRadius = 12.0;

// A binary glTF 2.0 (.glb), deterministic (the same bytes on every call):
// - nodes: MakeDemoWalk's skeleton (same joint names, order, hierarchy and
//   rest translations; End Sites have no node), in centimetres like the BVH,
//   so its poses and the demo_walk clip's are interchangeable (a viewer that
//   assumes glTF's metres shows it 100× too large). The root node Hips holds
//   the mesh and its skin: a separate mesh node would become a 20th joint on
//   import. Hips' rest transform is the identity, so that placement changes
//   nothing in any viewer (a skinned mesh's node transform is ignored).
// - one skin over all joints, skeleton = Hips. The mesh is modelled and
//   bound with the arms 40° out (an A-pose; the inverse bind matrices are
//   that pose's), not in the rest pose with the arms hanging, where the
//   automatic weights would let each hand move the thigh beside it;
// - mesh "body": one closed tube per body part (tapered capsules for the
//   limbs and neck, a rounded box for the torso, ellipsoids for head and
//   hands), POSITION, NORMAL, 16-bit indices, JOINTS_0/WEIGHTS_0 from
//   BindMesh's bone heat (each part is its own surface, so heat never
//   leaks from a leg to the other or from an arm into the torso), at most 4
//   influences;
// - animation "walk": the demo walk clip at its 30 fps frames, a rotation
//   channel per joint and the root's translation, LINEAR.
StatusOr<std::string> MakeDemoCharacterGlb();

}  // namespace armature
