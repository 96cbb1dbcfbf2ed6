// glTF 2.0 (.gltf, .glb) through the Debian assimp package, with the checks assimp lacks done first.
#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <nlohmann/json.hpp>

#include <cfloat>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rayscout/core/file_extension.h"
#include "core/private/little_endian.h"
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

// Word `at` bytes into the file, little-endian (the caller checked the size).
uint32_t le32(const std::string& s, size_t at) { return get_u32(s.data() + at); }

constexpr uint32_t kJsonChunk = 0x4E4F534Au;  // "JSON"

// The length that a glTF 2.0 .glb declares for its first chunk when that is a JSON chunk (sec. 4.4:
// a 12-byte header, then the chunk's length and type); empty for any other data.
std::optional<uint32_t> glb_json_chunk_length(const std::string& data) {
  if (data.size() < 20 || data.compare(0, 4, "glTF") != 0 || le32(data, 4) != 2 || le32(data, 16) != kJsonChunk) return {};
  return le32(data, 12);
}

// The JSON text of a glTF file: all of a .gltf, the first chunk of a glTF 2.0 .glb when it is a
// complete JSON chunk; empty when there is none.
std::string_view json_text(const std::string& data, bool binary) {
  if (!binary) return data;
  const std::optional<uint32_t> length = glb_json_chunk_length(data);
  if (!length || *length > data.size() - 20) return {};
  return std::string_view(data).substr(20, *length);
}

// A glTF 2.0 .glb whose JSON chunk declares more bytes than the file holds: assimp allocates
// the declared length before it reads (a 764-byte file with a length of 4 GB took 4 GB of
// memory and half a minute), so this is said before assimp sees the file. Empty otherwise.
std::string overrunning_json_chunk(const std::string& data) {
  const std::optional<uint32_t> length = glb_json_chunk_length(data);
  if (!length || *length <= data.size() - 20) return "";
  return "truncated: the JSON chunk declares " + std::to_string(*length) + " bytes, the file has " +
         std::to_string(data.size() - 20) + " after the chunk header";
}

// nlohmann's message for text that does not parse (the caller knows it does not).
std::string json_error(std::string_view text) {
  try {
    [[maybe_unused]] const nlohmann::json doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    return detail::invalid_json(e.what());
  }
  return "invalid JSON";
}

// What is wrong with a glTF file assimp could not read, where assimp only says "No suitable
// reader found for the file format": the container, the JSON, or its top level. Empty when
// none of these is wrong (then assimp's own message is the best there is). doc: the JSON,
// parsed once by the caller (discarded when it does not parse).
std::string container_defect(const std::string& data, bool binary, const nlohmann::json& doc) {
  if (binary) {
    if (data.size() < 4 || data.compare(0, 4, "glTF") != 0) return "not a binary glTF file (it does not start with \"glTF\")";
    if (data.size() < 12) return "truncated: " + std::to_string(data.size()) + " bytes, shorter than the 12-byte header";
    if (le32(data, 4) != 2) return "";  // glTF 1.0 (another layout) or unknown: assimp's message
    if (le32(data, 8) > data.size())
      return "truncated: the header declares " + std::to_string(le32(data, 8)) + " bytes, the file has " +
             std::to_string(data.size());
    if (json_text(data, true).empty()) return "the first chunk is not a complete JSON chunk";
  } else if (detail::skip_bom(data) != data.data()) {
    return "starts with a byte order mark, which glTF JSON must not have";
  }
  if (doc.is_discarded()) return json_error(json_text(data, binary));
  if (!doc.is_object()) return std::string("the JSON is ") + doc.type_name() + ", not an object";
  if (!doc.contains("asset")) return "no \"asset\" (glTF requires asset.version)";
  const nlohmann::json& asset = doc["asset"];
  if (!asset.is_object() || !asset.contains("version") || !asset["version"].is_string())
    return "asset.version is missing or not a string (glTF requires it)";
  if (const std::string version = asset["version"].get<std::string>(); !version.starts_with("2"))
    return "asset.version is \"" + printable(version) + "\", not 2.x (rayscout reads glTF 2.0)";
  return "";
}

// The node indices listed in j[key] (a node's "children", a scene's "nodes"), in order; entries
// that are not indices of `nodes` are left to assimp to report.
std::vector<size_t> node_list(const nlohmann::json& j, const char* key, size_t nodes) {
  std::vector<size_t> list;
  if (!j.is_object() || !j.contains(key) || !j[key].is_array()) return list;
  for (const nlohmann::json& n : j[key])
    if (n.is_number_unsigned() && n.get<uint64_t>() < nodes) list.push_back(n.get<size_t>());
  return list;
}

std::string node_name(size_t i) { return "nodes[" + std::to_string(i) + "]"; }

// Each node's parent (SIZE_MAX for none); a node listed as a child twice, or by two parents, is an error.
std::vector<size_t> node_parents(const nlohmann::json& nodes, const std::string& file) {
  std::vector<size_t> parent(nodes.size(), SIZE_MAX);
  for (size_t i = 0; i < nodes.size(); ++i) {
    for (const size_t child : node_list(nodes[i], "children", nodes.size())) {
      if (parent[child] == i)
        throw InputError(file + ": " + node_name(i) + " lists " + node_name(child) + " twice as a child");
      if (parent[child] != SIZE_MAX)
        throw InputError(file + ": " + node_name(child) + " is a child of " + node_name(parent[child]) + " and of " +
                         node_name(i) + ": glTF nodes form a tree, one parent each");
      parent[child] = i;
    }
  }
  return parent;
}

// glTF nodes form a forest: a node has at most one parent, and a scene's roots have none and are
// listed once each (glTF 2.0 sec. 3.5.1, 3.5.2). assimp does not check, and copies a node once per
// path to it: 40 nodes each listing the next one twice took minutes and gigabytes, and a root listed
// twice gave two copies of its triangles. Said before assimp sees the file.
void check_node_tree(const nlohmann::json& doc, const std::string& file) {
  if (!doc.is_object() || !doc.contains("nodes") || !doc["nodes"].is_array()) return;
  const nlohmann::json& nodes = doc["nodes"];
  const std::vector<size_t> parent = node_parents(nodes, file);
  if (!doc.contains("scenes") || !doc["scenes"].is_array()) return;
  for (size_t s = 0; s < doc["scenes"].size(); ++s) {
    std::vector<bool> listed(nodes.size(), false);
    for (const size_t root : node_list(doc["scenes"][s], "nodes", nodes.size())) {
      const std::string at = file + ": scenes[" + std::to_string(s) + "] lists " + node_name(root);
      if (listed[root]) throw InputError(at + " twice as a root");
      if (parent[root] != SIZE_MAX)
        throw InputError(at + " as a root, but it is a child of " + node_name(parent[root]) +
                         ": glTF nodes form a tree, one parent each");
      listed[root] = true;
    }
  }
}

// assimp 5.2 says that it dropped faces with out-of-range indices only to its logger; this
// collects its warnings and errors while it reads one file, through the process's logger if
// there is one, else through one of its own.
class AssimpMessages {
 public:
  AssimpMessages() : own_logger_(Assimp::DefaultLogger::isNullLogger()) {
    if (own_logger_) Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
    Assimp::DefaultLogger::get()->attachStream(stream_, kSeverity);
  }
  ~AssimpMessages() {
    Assimp::DefaultLogger::get()->detachStream(stream_, kSeverity);  // ownership comes back
    delete stream_;
    if (own_logger_) Assimp::DefaultLogger::kill();
  }
  AssimpMessages(const AssimpMessages&) = delete;
  AssimpMessages& operator=(const AssimpMessages&) = delete;
  bool contains(std::string_view text) const {
    for (const std::string& m : stream_->messages)
      if (m.find(text) != std::string::npos) return true;
    return false;
  }

 private:
  struct Stream : Assimp::LogStream {
    std::vector<std::string> messages;
    void write(const char* message) override { messages.emplace_back(message); }
  };
  static constexpr unsigned kSeverity = Assimp::Logger::Warn | Assimp::Logger::Err;
  bool own_logger_;
  Stream* stream_ = new Stream;
};

// KHR_materials_emissive_strength (emission = emissiveFactor * emissiveStrength) of the
// file's materials, by name: assimp 5.2 ignores the extension and imports materials in the
// order meshes first use them, not in file order, so the name is the only link. A strength
// that cannot be placed (no name, a name two materials share, a name assimp cuts or cannot
// hold) is ignored with a warning; so are all of them when the JSON is not strict UTF-8 JSON
// (assimp reads some files nlohmann rejects, e.g. Latin-1 names).
std::map<std::string, float> emissive_strengths(std::string_view text, const nlohmann::json& doc,
                                                const std::string& file, std::vector<std::string>& warnings) {
  constexpr std::string_view kExtension = "KHR_materials_emissive_strength";
  std::map<std::string, float> strength;
  if (text.find(kExtension) == std::string_view::npos) return strength;
  if (doc.is_discarded()) {
    warnings.push_back(file + ": " + std::string(kExtension) + " ignored: " + json_error(text));
    return strength;
  }
  if (!doc.is_object() || !doc.contains("materials") || !doc["materials"].is_array()) return strength;
  const nlohmann::json::json_pointer key("/extensions/KHR_materials_emissive_strength/emissiveStrength");
  const nlohmann::json& materials = doc["materials"];
  std::map<std::string, int> uses;
  for (const auto& m : materials)
    if (m.is_object() && m.contains("name") && m["name"].is_string()) ++uses[m["name"].get<std::string>()];
  for (size_t i = 0; i < materials.size(); ++i) {
    const nlohmann::json& m = materials[i];
    if (!m.is_object() || !m.contains(key)) continue;
    const std::string at = file + ": materials[" + std::to_string(i) + "]";
    if (!m[key].is_number() || !(m[key].get<double>() >= 0 && m[key].get<double>() <= FLT_MAX))
      throw InputError(at + ": emissiveStrength must be a number in [0, 3.4e38] (float)");
    const std::string name = m.contains("name") && m["name"].is_string() ? m["name"].get<std::string>() : "";
    const char* unplaced = name.empty()                    ? "it has no name"
                           : uses[name] > 1                ? "its name is not unique"
                           : name.size() >= MAXLEN         ? "assimp cuts its name"
                           : name.find('\0') != name.npos ? "its name holds a NUL"
                                                           : nullptr;
    if (unplaced)
      warnings.push_back(at + ": " + std::string(kExtension) + " ignored (" + unplaced +
                         ", and the name is how rayscout finds it after assimp's import)");
    else
      strength[name] = m[key].get<float>();
  }
  return strength;
}

// Keeps only the materials some face uses: assimp appends a default material (for primitives
// without one) to every glTF, which would otherwise be listed with 0 triangles.
void drop_unused_materials(Mesh& mesh) {
  std::vector<uint32_t> remap(mesh.materials.size(), UINT32_MAX);
  std::vector<Material> used;
  for (uint32_t& m : mesh.face_materials) {
    if (remap[m] == UINT32_MAX) {
      remap[m] = uint32_t(used.size());
      used.push_back(mesh.materials[m]);
    }
    m = remap[m];
  }
  mesh.materials = std::move(used);
}

// One of assimp's materials through the MTL mapping (docs/scene-format.md), emission scaled by its
// KHR_materials_emissive_strength; unnamed ones are "material<index>".
Material gltf_material(const aiMaterial* m, unsigned index, const std::map<std::string, float>& strengths,
                       const std::string& file, std::vector<std::string>& warnings) {
  aiString ai_name;
  const bool named = m->Get(AI_MATKEY_NAME, ai_name) == AI_SUCCESS && ai_name.length;
  const std::string name = named ? ai_name.C_Str() : "material" + std::to_string(index);
  float ns = 0;
  m->Get(AI_MATKEY_SHININESS, ns);
  const Vec3 kd = color(m, AI_MATKEY_COLOR_DIFFUSE, Vec3(0.8f));
  const Vec3 ks = color(m, AI_MATKEY_COLOR_SPECULAR, Vec3(0.0f));
  Vec3 ke = color(m, AI_MATKEY_COLOR_EMISSIVE, Vec3(0.0f));
  if (auto it = strengths.find(name); named && it != strengths.end()) ke *= it->second;
  // As in MTL and JSON materials: a negative or non-finite colour would make negative or NaN radiance.
  for (const auto& [what, c] : {std::pair{"base colour", kd}, {"specular colour", ks}, {"emission", ke}}) {
    const std::string material = file + ": material \"" + printable(name) + "\": " + what;
    if (!is_finite(c)) throw InputError(material + " beyond float range");
    if (c.x < 0 || c.y < 0 || c.z < 0) throw InputError(material + " components must be >= 0");
  }
  Material mat = material_from_mtl(name, kd, ks, ns, 2, ke);
  if (std::string warning = conserve_energy_with_warning(mat, file); !warning.empty()) warnings.push_back(std::move(warning));
  return mat;
}

// Appends one instance of assimp's mesh `index` in world space (`global`); a mirroring transform
// keeps each face's front by swapping two corners (corners_after).
void add_instance(const aiMesh& am, unsigned index, const aiMatrix4x4& global, const std::string& file, Mesh& mesh) {
  const bool mirrored = global.Determinant() < 0;
  const uint32_t base = uint32_t(mesh.positions.size());
  for (unsigned v = 0; v < am.mNumVertices; ++v) {
    const aiVector3D w = global * am.mVertices[v];
    const Vec3 p(w.x, w.y, w.z);
    if (!is_finite(p))
      throw InputError(file + ": mesh " + std::to_string(index) + " vertex " + std::to_string(v) + ": coordinate is not finite");
    mesh.positions.push_back(p);
  }
  const uint32_t material = am.mMaterialIndex < mesh.materials.size() ? am.mMaterialIndex : 0;
  for (unsigned f = 0; f < am.mNumFaces; ++f) {
    const aiFace& face = am.mFaces[f];
    if (face.mNumIndices != 3) continue;
    for (int k = 0; k < 3; ++k)
      if (face.mIndices[k] >= am.mNumVertices)
        throw InputError(file + ": mesh " + std::to_string(index) + " face " + std::to_string(f) + ": index " +
                         std::to_string(face.mIndices[k]) + " out of range (" + detail::count_of(am.mNumVertices, "vertex") + ")");
    mesh.faces.push_back(
        detail::corners_after({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]}, mirrored));
    mesh.face_materials.push_back(material);
  }
}

// Every instance of a triangle mesh in the node tree, depth first in child order. The node
// transforms are applied here, not by aiProcess_PreTransformVertices, which keeps the corner
// order of a mirrored node.
void add_node_tree(const aiScene& scene, const std::string& file, Mesh& mesh) {
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack;
  if (scene.mRootNode) stack.push_back({scene.mRootNode, scene.mRootNode->mTransformation});
  while (!stack.empty()) {
    const auto [node, global] = stack.back();
    stack.pop_back();
    for (unsigned c = node->mNumChildren; c-- > 0;)
      stack.push_back({node->mChildren[c], global * node->mChildren[c]->mTransformation});
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const unsigned index = node->mMeshes[k];
      if (index < scene.mNumMeshes && (scene.mMeshes[index]->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
        add_instance(*scene.mMeshes[index], index, global, file, mesh);
    }
  }
}

}  // namespace

Mesh read_gltf(const std::filesystem::path& path) {
  const bool binary = lower_extension(path) == ".glb";
  const std::string file = detail::display_name(path), data = detail::read_file(path);
  const std::string_view json = json_text(data, binary);
  detail::check_json_nesting(json, file);
  if (binary)
    if (const std::string overrun = overrunning_json_chunk(data); !overrun.empty()) throw InputError(file + ": " + overrun);
  // Discarded when it does not parse: assimp reads some files nlohmann rejects (Latin-1 names).
  const nlohmann::json doc = nlohmann::json::parse(json, nullptr, /*allow_exceptions=*/false);
  check_node_tree(doc, file);
  Assimp::Importer importer;
  const AssimpMessages messages;
  // From the path, not from `data`: buffers and images may be files beside it.
  const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_SortByPType);
  if (messages.contains("out-of-range indices"))  // also when every face was dropped
    throw InputError(file + ": a primitive's indices reach past its vertex count (assimp dropped those faces)");
  if (!scene) {
    const std::string defect = container_defect(data, binary, doc);
    // glTF 2.0 sec. 3.5.1: an asset without scenes "SHOULD be treated as a library of individual
    // entities"; rendering all its root nodes would place alternatives on top of each other.
    if (defect.empty() && doc.is_object() &&
        (!doc.contains("scenes") || (doc["scenes"].is_array() && doc["scenes"].empty())))
      throw InputError(file + ": no scenes: a glTF file without scenes is a library of assets, not a scene "
                              "to render (glTF 2.0 sec. 3.5.1); list its root nodes in a scene");
    throw InputError(file + ": " + (defect.empty() ? "assimp cannot read it: " + std::string(importer.GetErrorString()) : defect));
  }
  Mesh mesh;
  const std::map<std::string, float> strengths = emissive_strengths(json, doc, file, mesh.warnings);
  for (unsigned i = 0; i < scene->mNumMaterials; ++i)
    mesh.materials.push_back(gltf_material(scene->mMaterials[i], i, strengths, file, mesh.warnings));
  if (mesh.materials.empty()) mesh.materials.push_back(Material{.name = "default"});
  add_node_tree(*scene, file, mesh);
  if (mesh.faces.empty()) throw InputError(file + ": no triangles (empty mesh)");
  drop_unused_materials(mesh);
  return mesh;
}

}  // namespace rayscout
