// Makes tests/data/fbx/mixamo_walk.fbx, a Mixamo-style FBX: assimp reads CMU
// 01_01 (../shared/data/bvh/cmu_01_01.bvh, whose joint names are mostly
// Mixamo's: Hips, Spine, LeftUpLeg, LeftForeArm, …), keeps its first `frames`
// keys, prefixes every node and channel with "mixamorig:" as Mixamo's
// downloads are named, and writes it with assimp's FBX exporter (ASCII).
// The skeleton mesh assimp's BVH reader adds is dropped: the file is a rig and
// its animation, as Mixamo's "without skin" downloads are. Not part of the
// build; run once when the file needs remaking:
//   g++ -std=c++20 -O1 tests/tools/make_mixamo_fbx.cc -lassimp -o /tmp/make_mixamo_fbx
//   /tmp/make_mixamo_fbx ../shared/data/bvh/cmu_01_01.bvh tests/data/fbx/mixamo_walk.fbx 30
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

void Rename(aiString& name) { name.Set("mixamorig:" + std::string(name.C_Str())); }

void RenameNodes(aiNode* node) {
  Rename(node->mName);
  node->mNumMeshes = 0;
  for (unsigned c = 0; c < node->mNumChildren; ++c) RenameNodes(node->mChildren[c]);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: make_mixamo_fbx <in.bvh> <out.fbx> [frames]\n");
    return 2;
  }
  const unsigned frames = argc > 3 ? static_cast<unsigned>(std::atoi(argv[3])) : 60;
  Assimp::Importer importer;
  const aiScene* read = importer.ReadFile(argv[1], 0);
  if (read == nullptr) {
    std::fprintf(stderr, "%s\n", importer.GetErrorString());
    return 1;
  }
  aiScene* scene = importer.GetOrphanedScene();
  RenameNodes(scene->mRootNode);
  scene->mNumMeshes = 0;
  // assimp's exporter writes the root's children only: the Hips go under a new root.
  aiNode* root = new aiNode("RootNode");
  root->addChildren(1, &scene->mRootNode);
  scene->mRootNode = root;
  for (unsigned a = 0; a < scene->mNumAnimations; ++a) {
    aiAnimation* anim = scene->mAnimations[a];
    anim->mName.Set("walk");
    // The exporter takes key times as seconds: ticks converted here.
    const double ticks = anim->mTicksPerSecond > 0 ? anim->mTicksPerSecond : 25;
    anim->mTicksPerSecond = 1;
    double last = 0;
    for (unsigned c = 0; c < anim->mNumChannels; ++c) {
      aiNodeAnim* channel = anim->mChannels[c];
      Rename(channel->mNodeName);
      // Counts shortened in place; assimp frees the arrays whole.
      channel->mNumPositionKeys = std::min(channel->mNumPositionKeys, frames);
      channel->mNumRotationKeys = std::min(channel->mNumRotationKeys, frames);
      channel->mNumScalingKeys = std::min(channel->mNumScalingKeys, frames);
      for (unsigned k = 0; k < channel->mNumPositionKeys; ++k) channel->mPositionKeys[k].mTime /= ticks;
      for (unsigned k = 0; k < channel->mNumRotationKeys; ++k) channel->mRotationKeys[k].mTime /= ticks;
      for (unsigned k = 0; k < channel->mNumScalingKeys; ++k) channel->mScalingKeys[k].mTime /= ticks;
      if (channel->mNumRotationKeys) last = std::max(last, channel->mRotationKeys[channel->mNumRotationKeys - 1].mTime);
    }
    anim->mDuration = last;
  }
  Assimp::Exporter exporter;
  if (exporter.Export(scene, "fbxa", argv[2]) != AI_SUCCESS) {
    std::fprintf(stderr, "%s\n", exporter.GetErrorString());
    return 1;
  }
  return 0;
}
