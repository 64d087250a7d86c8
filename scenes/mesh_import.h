// glint — triangle meshes from .ply and .obj files (through Assimp) into a SceneDescription.
#pragma once

#include <string>

#include "scenes/description.h"

namespace glint {

// True for the extensions loadMeshFile reads (.ply, .obj; any case).
bool isMeshFile(const std::string& path);

// Appends the triangles of a .ply or .obj file to `scene`: polygons are triangulated and
// identical vertices joined; one MeshDesc per mesh in the file (positions, and normals when the
// file has them), each placed once with the identity transform and the default material.
// Points, lines and materials in the file are not used (points and lines are reported in
// scene->warnings). Throws SceneError naming the file: "bunny.ply: cannot read mesh: <why>".
void loadMeshFile(const std::string& path, SceneDescription* scene);

}  // namespace glint
