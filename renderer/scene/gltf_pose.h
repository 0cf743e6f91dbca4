// The static pose of glTF meshes: morph targets at their default weights and skinning by the
// joints' rest transforms (glTF 2.0 3.7.2.2 and 3.7.3). tex renders one moment, the one a
// glTF viewer shows before any animation plays: node.weights (else mesh.weights) blend the
// targets' displacements in, and a skinned mesh is placed by its joints, not by its own node.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "renderer/scene/scene_description.h"

namespace tex::render {

// Adds sum_i weights[i] x target i's POSITION / NORMAL / TANGENT displacements to `prim`
// (read from `gltfPrimitive`'s targets; vertex counts as in `prim`). Normals and tangents stay
// unnormalised, as the spec leaves them (the renderer normalises at the hit). Returns "" or the
// problem (no file name); `ignored` gets the names of target attributes not applied.
std::string applyMorphTargets(const tinygltf::Model& model, const tinygltf::Primitive& gltfPrimitive,
                              const std::vector<double>& weights, MeshPrimitive& prim, std::vector<std::string>& ignored);

// Linear blend skinning of `prim` (object space of the skinned mesh) into world space:
// p' = sum_k w_k jointMatrices[j_k] p over JOINTS_n / WEIGHTS_n, where jointMatrices[j] is the
// joint's world transform times its inverse bind matrix. Normals and tangents go through the
// blended matrix's inverse transpose (its linear part). Weights are divided by their sum; a
// vertex whose weights sum to 0 (or that has no JOINTS_n / WEIGHTS_n at all) is placed by
// `fallback` (the mesh node's world transform). Returns "" or the problem.
std::string skinToWorld(const tinygltf::Model& model, const tinygltf::Primitive& gltfPrimitive,
                        const std::vector<Mat4>& jointMatrices, const Mat4& fallback, MeshPrimitive& prim);

// The first joint of `skin` that is not a node of the rendered scene (no world transform in
// `worldOfNode`), or -1.
int jointOutsideScene(const tinygltf::Skin& skin, const std::vector<std::optional<Mat4>>& worldOfNode);

// The skin's joint matrices: world(joint j) x inverseBindMatrices[j] (identity when the skin
// has none). `worldOfNode` holds the world transform of every node of the scene; a joint
// outside it is an error.
std::string jointMatrices(const tinygltf::Model& model, const tinygltf::Skin& skin,
                          const std::vector<std::optional<Mat4>>& worldOfNode, std::vector<Mat4>& out);

}  // namespace tex::render
