// glint — PLY and OBJ import through Assimp.
#include "scenes/mesh_import.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <filesystem>

namespace glint {

namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// The normals of `mesh`, or none when any of them cannot be made unit length (an OBJ may hold
// zero normals): shading then falls back to the geometric normal instead of failing the load.
std::vector<Vec3f> unitNormals(const aiMesh& mesh) {
  std::vector<Vec3f> normals(mesh.mNumVertices);
  for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
    Vec3f n{mesh.mNormals[i].x, mesh.mNormals[i].y, mesh.mNormals[i].z};
    float len = length(n);
    if (!(len > 0) || !std::isfinite(len)) return {};
    normals[i] = n / len;
  }
  return normals;
}

}  // namespace

bool isMeshFile(const std::string& path) {
  std::string ext = lowerExtension(path);
  return ext == ".ply" || ext == ".obj";
}

void loadMeshFile(const std::string& path, SceneDescription* scene) {
  SourceLocation where{path, ""};
  Assimp::Importer importer;
  // Only triangles matter; no normals are generated (meshes without them shade with the
  // geometric normal, as glTF meshes without NORMAL do). Validation runs before the other
  // steps: without it a truncated binary PLY (faces indexing missing vertices) crashes them.
  const aiScene* ai =
      importer.ReadFile(path, aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                                  aiProcess_JoinIdenticalVertices);
  if (!ai) throw SceneError(where, std::string("cannot read mesh: ") + importer.GetErrorString());
  if (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
    throw SceneError(where, "cannot read mesh: the file is incomplete");

  size_t triangles = 0;
  for (unsigned m = 0; m < ai->mNumMeshes; ++m) {
    const aiMesh& am = *ai->mMeshes[m];
    MeshDesc mesh;
    mesh.name = am.mName.length ? std::string(am.mName.C_Str()) : "mesh " + std::to_string(m);
    mesh.where = where;
    mesh.positions.resize(am.mNumVertices);
    for (unsigned i = 0; i < am.mNumVertices; ++i) {
      Vec3f p{am.mVertices[i].x, am.mVertices[i].y, am.mVertices[i].z};
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw SceneError(
            where, "mesh '" + mesh.name + "': vertex " + std::to_string(i) + " is not finite");
      mesh.positions[i] = p;
    }
    if (am.HasNormals()) {
      mesh.normals = unitNormals(am);
      if (mesh.normals.empty())
        scene->warnings.push_back(path + ": mesh '" + mesh.name +
                                  "': normals with zero length ignored");
    }
    size_t skipped = 0;
    mesh.indices.reserve(size_t(am.mNumFaces) * 3);
    for (unsigned f = 0; f < am.mNumFaces; ++f) {
      const aiFace& face = am.mFaces[f];
      if (face.mNumIndices != 3) {  // points and lines survive triangulation
        ++skipped;
        continue;
      }
      for (unsigned k = 0; k < 3; ++k) {
        if (face.mIndices[k] >= am.mNumVertices)
          throw SceneError(where, "mesh '" + mesh.name + "': face " + std::to_string(f) +
                                      " refers to a missing vertex");
        mesh.indices.push_back(face.mIndices[k]);
      }
    }
    if (skipped)
      scene->warnings.push_back(path + ": mesh '" + mesh.name + "': " + std::to_string(skipped) +
                                " points or lines ignored");
    if (mesh.indices.empty()) continue;
    triangles += mesh.indices.size() / 3;
    InstanceDesc inst;
    inst.mesh = int(scene->meshes.size());
    inst.node = mesh.name;
    inst.where = where;
    scene->meshes.push_back(std::move(mesh));
    scene->instances.push_back(std::move(inst));
  }
  if (triangles == 0) throw SceneError(where, "cannot read mesh: the file has no triangles");
}

}  // namespace glint
