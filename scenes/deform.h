// glint — posing skinned and morphed meshes: a mesh description and an instance of it, evaluated
// at a time (seconds) into the positions, normals and tangents the builder meshes.
//
// Morph targets first, then skinning, as glTF orders them: each attribute becomes
// base + sum_i w_i delta_i with the instance's weights at that time (its animated weights, else
// its node's, else the mesh's defaults); a skinned vertex then goes to the world by the blend
// sum_k w_k J_k of its four joints' matrices J = worldFromJoint(time) · inverseBind (linear
// blend skinning; weights renormalised to sum 1). Normals follow the blend's cofactor matrix,
// tangents its linear part. A posed mesh is built once per frame: at the shutter's middle, and
// when its pose changes inside the shutter also at evenly spaced times over it (the time steps
// of deformation blur, see scenes/build.cpp and TriangleMesh::positionSteps).
#pragma once

#include <vector>

#include "scenes/description.h"

namespace glint {

// Whether instance `inst` must be posed (it is skinned, or its mesh has morph targets).
bool deforms(const SceneDescription& scene, const InstanceDesc& inst);
// Whether its pose changes over time (animated weights or an animated joint).
bool deformationAnimated(const SceneDescription& scene, const InstanceDesc& inst);
// The morph weights of `inst` at `time`, one per target of its mesh.
std::vector<float> morphWeightsAt(const SceneDescription& scene, const InstanceDesc& inst,
                                  double time);
// The instance's mesh posed at `time`: a copy of its MeshDesc whose positions, normals and
// tangents are posed (in world space when skinned, else in the instance's object space), with
// no targets or joints left.
MeshDesc posedMesh(const SceneDescription& scene, const InstanceDesc& inst, double time);
// Its posed positions alone (what framing needs), without copying the rest of the mesh.
std::vector<Vec3f> posedPositions(const SceneDescription& scene, const InstanceDesc& inst,
                                  double time);
// Its posed positions and normals (normals empty when the mesh has none).
void posedVertices(const SceneDescription& scene, const InstanceDesc& inst, double time,
                   std::vector<Vec3f>* positions, std::vector<Vec3f>* normals);

}  // namespace glint
