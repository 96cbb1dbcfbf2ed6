// glTF 2.0 (and other assimp formats) through the Debian assimp package.
#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "rayscout/scene/mesh.h"
#include "scene_builder.h"
#include "text_parse.h"

namespace rayscout {
namespace {

Vec3 color(const aiMaterial* m, const char* key, unsigned type, unsigned idx, Vec3 fallback) {
  aiColor3D c;
  if (m->Get(key, type, idx, c) == AI_SUCCESS) return {c.r, c.g, c.b};
  return fallback;
}

}  // namespace

Mesh read_assimp(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw InputError(detail::display_name(path) + ": cannot open: No such file or directory");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_SortByPType);
  if (!scene) throw InputError(detail::display_name(path) + ": " + importer.GetErrorString());
  Mesh mesh;
  for (unsigned i = 0; i < scene->mNumMaterials; ++i) {
    const aiMaterial* m = scene->mMaterials[i];
    aiString name;
    std::string n = m->Get(AI_MATKEY_NAME, name) == AI_SUCCESS && name.length ? name.C_Str() : "material" + std::to_string(i);
    float ns = 0;
    m->Get(AI_MATKEY_SHININESS, ns);
    Vec3 kd = color(m, AI_MATKEY_COLOR_DIFFUSE, Vec3(0.8f));
    Vec3 ks = color(m, AI_MATKEY_COLOR_SPECULAR, Vec3(0.0f));
    Vec3 ke = color(m, AI_MATKEY_COLOR_EMISSIVE, Vec3(0.0f));
    mesh.materials.push_back(material_from_mtl(n, kd, ks, ns, 2, ke));
  }
  if (mesh.materials.empty()) mesh.materials.push_back(Material{.name = "default"});
  // Every instance of a mesh in the node tree, in world space. The node transforms are applied
  // here, not by aiProcess_PreTransformVertices, which keeps the corner order of a mirrored
  // node (corners_after).
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> nodes;
  if (scene->mRootNode) nodes.push_back({scene->mRootNode, scene->mRootNode->mTransformation});
  while (!nodes.empty()) {
    const auto [node, global] = nodes.back();
    nodes.pop_back();
    for (unsigned c = node->mNumChildren; c-- > 0;)
      nodes.push_back({node->mChildren[c], global * node->mChildren[c]->mTransformation});
    const bool mirrored = global.Determinant() < 0;
    for (unsigned n = 0; n < node->mNumMeshes; ++n) {
      const unsigned mi = node->mMeshes[n];
      if (mi >= scene->mNumMeshes) continue;
      const aiMesh* am = scene->mMeshes[mi];
      if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      const uint32_t base = uint32_t(mesh.positions.size());
      for (unsigned v = 0; v < am->mNumVertices; ++v) {
        const aiVector3D w = global * am->mVertices[v];
        const Vec3 p(w.x, w.y, w.z);
        if (!is_finite(p))
          throw InputError(detail::display_name(path) + ": mesh " + std::to_string(mi) + " vertex " + std::to_string(v) +
                           ": coordinate is not finite");
        mesh.positions.push_back(p);
      }
      const uint32_t mat = am->mMaterialIndex < mesh.materials.size() ? am->mMaterialIndex : 0;
      for (unsigned f = 0; f < am->mNumFaces; ++f) {
        const aiFace& face = am->mFaces[f];
        if (face.mNumIndices != 3) continue;
        for (int k = 0; k < 3; ++k)
          if (face.mIndices[k] >= am->mNumVertices)
            throw InputError(detail::display_name(path) + ": mesh " + std::to_string(mi) + " face " + std::to_string(f) +
                             ": index " + std::to_string(face.mIndices[k]) + " out of range (" +
                             std::to_string(am->mNumVertices) + " vertices)");
        mesh.faces.push_back(
            detail::corners_after({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]}, mirrored));
        mesh.face_materials.push_back(mat);
      }
    }
  }
  if (mesh.faces.empty()) throw InputError(detail::display_name(path) + ": no triangles (empty mesh)");
  return mesh;
}

}  // namespace rayscout
