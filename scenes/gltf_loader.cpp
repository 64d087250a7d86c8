// glint — glTF 2.0 loading: GLB container, URI checks, tinygltf decoding, accessors, and the
// walk over the node tree that fills the SceneDescription.
//
// Three passes: (1) the JSON is parsed with nlohmann and read into validated structs
// (gltf_document.h) so every error carries a JSON pointer; (2) URIs are checked against the
// scene folder and tinygltf decodes buffers, data URIs and images, reading files only through
// callbacks that refuse to leave the folder; (3) accessor data is read with bounds checks and
// the default scene is instanced.
#include "scenes/gltf_loader.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <system_error>
#include <tuple>
#include <type_traits>

#include "image/oiio/plugin.h"
#include "materials/image_texture.h"
#include "scenes/gltf_document.h"
#include "scenes/gltf_draco.h"
#include "scenes/gltf_meshopt.h"
#include "scenes/json_util.h"

namespace glint {

namespace fs = std::filesystem;
using gltf::Accessor;
using gltf::Document;

namespace {

// ---------------------------------------------------------------------------------------------
// GLB container
// ---------------------------------------------------------------------------------------------

constexpr uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;   // "BIN\0"

uint32_t readU32(const std::string& bytes, size_t offset) {
  uint32_t v;
  std::memcpy(&v, bytes.data() + offset, 4);  // GLB is little-endian, as is every target
  return v;
}

bool hasGlbMagic(const std::string& bytes) {
  return bytes.size() >= 4 && readU32(bytes, 0) == kGlbMagic;
}

struct GlbChunks {
  std::string json;
  size_t binSize = 0;  // 0 = no BIN chunk
};

// Checks the 12-byte header and the chunk headers; tinygltf re-parses the container later but
// would report these problems without saying what is wrong.
GlbChunks parseGlb(const std::string& bytes, const std::string& file) {
  SourceLocation where{file, ""};
  size_t size = bytes.size();
  if (size < 12)
    throw SceneError(where, "truncated GLB: file has " + std::to_string(size) +
                                " bytes, less than the 12-byte header");
  if (readU32(bytes, 0) != kGlbMagic)
    throw SceneError(where, "not a binary glTF file (the first 4 bytes are not 'glTF')");
  uint32_t version = readU32(bytes, 4), length = readU32(bytes, 8);
  if (version != 2)
    throw SceneError(
        where, "unsupported GLB version " + std::to_string(version) + " (glint reads version 2)");
  if (length > size)
    throw SceneError(where, "truncated GLB: header says " + std::to_string(length) +
                                " bytes, file has " + std::to_string(size));
  if (length < size)
    throw SceneError(where, "GLB header says " + std::to_string(length) + " bytes, file has " +
                                std::to_string(size) + " (trailing data)");
  if (length < 20) throw SceneError(where, "truncated GLB: no JSON chunk");
  uint32_t jsonLength = readU32(bytes, 12), jsonType = readU32(bytes, 16);
  if (jsonType != kChunkJson) throw SceneError(where, "the first GLB chunk is not JSON");
  if (jsonLength > length - 20)
    throw SceneError(where, "truncated GLB: JSON chunk says " + std::to_string(jsonLength) +
                                " bytes, only " + std::to_string(length - 20) + " follow");
  GlbChunks chunks;
  chunks.json = bytes.substr(20, jsonLength);
  // The chunk is padded with spaces; tolerate NUL padding written by some exporters.
  while (!chunks.json.empty() && chunks.json.back() == '\0') chunks.json.pop_back();
  size_t offset = 20 + size_t(jsonLength);
  // Chunks start on 4-byte boundaries; unknown chunk types are skipped, as glTF requires.
  while (offset < length) {
    if (length - offset < 8)
      throw SceneError(where,
                       "truncated GLB: incomplete chunk header at byte " + std::to_string(offset));
    uint32_t chunkLength = readU32(bytes, offset), chunkType = readU32(bytes, offset + 4);
    if (chunkLength > length - offset - 8)
      throw SceneError(where, "truncated GLB: chunk at byte " + std::to_string(offset) + " says " +
                                  std::to_string(chunkLength) + " bytes, only " +
                                  std::to_string(length - offset - 8) + " follow");
    if (chunkType == kChunkBin) {
      if (offset != 20 + size_t(jsonLength))
        throw SceneError(where, "the BIN chunk must directly follow the JSON chunk");
      chunks.binSize = chunkLength;
    }
    offset += 8 + size_t(chunkLength);
  }
  return chunks;
}

// ---------------------------------------------------------------------------------------------
// URIs: stay inside the scene folder
// ---------------------------------------------------------------------------------------------

bool isDataUri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

std::string percentDecode(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(uint8_t(s[i + 1])) &&
        std::isxdigit(uint8_t(s[i + 2]))) {
      out += char(std::stoi(s.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

bool isInside(const fs::path& path, const fs::path& folder) {
  fs::path rel = path.lexically_relative(folder);
  return !rel.empty() && *rel.begin() != ".." && !rel.is_absolute();
}

fs::path canonicalOrSelf(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(p, ec);
  return ec ? p.lexically_normal() : c;
}

// The file a relative URI names, after checking that it stays inside `folder` (canonical) and
// can be read. Throws at `where` (the "uri" property) otherwise.
fs::path resolveUri(const std::string& uri, const fs::path& folder, const SourceLocation& where) {
  std::string decoded = percentDecode(uri);
  size_t colon = decoded.find(':'), slash = decoded.find('/');
  if (colon != std::string::npos && (slash == std::string::npos || colon < slash))
    throw SceneError(where, "unsupported URI scheme in '" + uri +
                                "' (only relative paths and "
                                "data URIs are read)");
  fs::path rel(decoded);
  if (rel.is_absolute() || !isInside(canonicalOrSelf(folder / rel), folder))
    throw SceneError(where, "'" + uri + "' leaves the scene folder");
  fs::path path = canonicalOrSelf(folder / rel);
  std::error_code ec;
  std::ifstream probe(path, std::ios::binary);
  if (!fs::is_regular_file(path, ec) || !probe)
    throw SceneError(where, "cannot read '" + uri + "'");
  return path;
}

// Checks every buffer and image source before tinygltf reads them.
void checkSources(const Document& doc, const fs::path& folder, const GlbChunks* glb) {
  for (size_t i = 0; i < doc.buffers.size(); ++i) {
    const gltf::Buffer& b = doc.buffers[i];
    SourceLocation uriLoc = b.where.child("uri");
    if (b.uri.empty() && b.fallback) continue;  // EXT_meshopt_compression: no data needed
    if (b.uri.empty()) {
      if (!glb || i != 0)
        throw SceneError(b.where, glb ? "only buffer 0 may refer to the GLB BIN chunk"
                                      : "missing 'uri' (only a .glb file may omit it)");
      if (glb->binSize < b.byteLength)
        throw SceneError(b.where.child("byteLength"), "byteLength is " +
                                                          std::to_string(b.byteLength) +
                                                          " but the GLB BIN chunk has " +
                                                          std::to_string(glb->binSize) + " bytes");
    } else if (isDataUri(b.uri)) {
      std::vector<unsigned char> data;
      std::string mime;
      if (!tinygltf::DecodeDataURI(&data, mime, b.uri, 0, false))
        throw SceneError(uriLoc,
                         "cannot decode the data URI (base64 with type "
                         "application/octet-stream or application/gltf-buffer expected)");
      if (data.size() != b.byteLength)
        throw SceneError(b.where.child("byteLength"),
                         "byteLength is " + std::to_string(b.byteLength) +
                             " but the data URI holds " + std::to_string(data.size()) + " bytes");
    } else {
      fs::path path = resolveUri(b.uri, folder, uriLoc);
      std::error_code ec;
      uintmax_t size = fs::file_size(path, ec);
      if (ec) throw SceneError(uriLoc, "cannot read '" + b.uri + "'");
      // tinygltf insists on an exact match; say so before it does.
      if (size != b.byteLength)
        throw SceneError(b.where.child("byteLength"),
                         "byteLength is " + std::to_string(b.byteLength) + " but '" + b.uri +
                             "' has " + std::to_string(size) + " bytes");
    }
  }
  for (const gltf::Image& im : doc.images) {
    if (im.uri.empty()) continue;
    if (isDataUri(im.uri)) {
      std::vector<unsigned char> data;
      std::string mime;
      if (!tinygltf::DecodeDataURI(&data, mime, im.uri, 0, false))
        throw SceneError(im.where.child("uri"), "cannot decode the data URI");
    } else {
      resolveUri(im.uri, folder, im.where.child("uri"));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// tinygltf with file access confined to the scene folder (the second line of defence)
// ---------------------------------------------------------------------------------------------

struct FolderGuard {
  fs::path folder;  // canonical
};

bool guardedPath(const std::string& path, void* user, fs::path* out) {
  const FolderGuard& guard = *static_cast<const FolderGuard*>(user);
  fs::path p = canonicalOrSelf(fs::absolute(fs::path(path)));
  if (!isInside(p, guard.folder)) return false;
  *out = p;
  return true;
}

bool guardedFileExists(const std::string& path, void* user) {
  fs::path p;
  std::error_code ec;
  return guardedPath(path, user, &p) && fs::is_regular_file(p, ec);
}

std::string guardedExpandFilePath(const std::string& path, void*) { return path; }

bool guardedReadWholeFile(std::vector<unsigned char>* out, std::string* err,
                          const std::string& path, void* user) {
  fs::path p;
  if (!guardedPath(path, user, &p)) {
    if (err) *err += "refusing to read '" + path + "' outside the scene folder\n";
    return false;
  }
  std::ifstream in(p, std::ios::binary);
  if (!in) {
    if (err) *err += "cannot read '" + path + "'\n";
    return false;
  }
  out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return !in.bad();
}

bool refuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "glint never writes glTF files\n";
  return false;
}

// The big-endian 32-bit integer at b (PNG lengths and sizes).
uint64_t bigEndian32(const unsigned char* b) {
  return uint64_t(b[0]) << 24 | uint64_t(b[1]) << 16 | uint64_t(b[2]) << 8 | b[3];
}

// The width and height a PNG or JPEG header states; false for other data or a header too short.
bool imageHeaderSize(const unsigned char* b, int size, uint64_t* width, uint64_t* height) {
  const auto be32 = [&](int i) { return bigEndian32(b + i); };
  const auto be16 = [&](int i) { return uint64_t(b[i]) << 8 | b[i + 1]; };
  if (size >= 24 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G') {
    *width = be32(16), *height = be32(20);
    return true;
  }
  if (size < 4 || b[0] != 0xFF || b[1] != 0xD8) return false;
  for (int i = 2; i + 9 < size && b[i] == 0xFF;) {
    const int marker = b[i + 1];
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      *height = be16(i + 5), *width = be16(i + 7);
      return true;
    }
    i += 2 + int(be16(i + 2));
  }
  return false;
}

// Embedded and referenced images are decoded by tinygltf (stb_image), which allocates what the
// header claims: a 100-byte PNG stating 60000 x 60000 pixels would ask for gigabytes (found by
// fuzzing). Larger than this is refused before decoding.
constexpr uint64_t kMaxImagePixels = uint64_t(1) << 26;  // 8192 x 8192

struct PreserveChannels {  // the layout of tinygltf's LoadImageDataOption
  bool preserveChannels = true;
};

bool loadImageWithinLimits(tinygltf::Image* image, const int index, std::string* err,
                           std::string* warn, int reqWidth, int reqHeight,
                           const unsigned char* bytes, int size, void*) {
  // stb_image also reserves what a PNG chunk's length field claims: a chunk cannot be longer
  // than the data that holds it.
  if (size >= 8 && bytes[0] == 0x89 && bytes[1] == 'P') {
    for (int64_t pos = 8; pos + 8 <= size;) {
      const uint64_t length = bigEndian32(bytes + pos);
      if (length > uint64_t(size - pos - 8)) {
        if (err)
          *err += "image " + std::to_string(index) + ": a PNG chunk claims " +
                  std::to_string(length) + " bytes, more than the image holds\n";
        return false;
      }
      pos += 12 + int64_t(length);  // length, type, data, CRC
    }
  }
  uint64_t w = 0, h = 0;
  if (imageHeaderSize(bytes, size, &w, &h) && w * h > kMaxImagePixels) {
    if (err)
      *err += "image " + std::to_string(index) + " is " + std::to_string(w) + " x " +
              std::to_string(h) + " pixels: glint reads glTF images up to " +
              std::to_string(kMaxImagePixels) + " pixels (8192 x 8192)\n";
    return false;
  }
  // Kept encoded: the builder decodes the images a render needs, in parallel
  // (TextureImages::addEncoded), and loading or `glint info` never pays for it.
  (void)warn, (void)reqWidth, (void)reqHeight;
  image->image.assign(bytes, bytes + size);
  return true;
}

// What tinygltf is given: the file with only the sections it decodes for glint (asset,
// buffers, buffer views, images: URIs, data URIs and the GLB's BIN chunk). Everything else
// comes from the first pass, so tinygltf checks nothing glint reads differently (a
// Draco-compressed primitive's indices accessor has no buffer view, which tinygltf rejects).
std::string forTinygltf(const std::string& bytes, bool binary, const nlohmann::json& json,
                        const Document& doc) {
  nlohmann::json reduced = nlohmann::json::object();
  for (const char* key : {"asset", "buffers", "bufferViews", "images"})
    if (json.contains(key)) reduced[key] = json[key];
  // EXT_meshopt_compression's fallback buffers may have no data: one byte stands in, so that
  // the buffer indices stay (no view of it is read; compressed views are decoded).
  for (size_t i = 0; i < doc.buffers.size(); ++i)
    if (doc.buffers[i].fallback && doc.buffers[i].uri.empty())
      reduced["buffers"][i] = {{"byteLength", 1},
                               {"uri", "data:application/octet-stream;base64,AA=="}};
  std::string text = reduced.dump();
  if (!binary) return text;
  // The GLB again: its header, the new JSON chunk (space-padded to 4 bytes), then every chunk
  // that followed the old one, unchanged.
  text.append((4 - text.size() % 4) % 4, ' ');
  const size_t rest = 20 + size_t(readU32(bytes, 12));
  const uint32_t length = uint32_t(20 + text.size() + (bytes.size() - rest));
  std::string glb;
  auto u32 = [&](uint32_t v) {
    for (int i = 0; i < 4; ++i) glb.push_back(char((v >> (8 * i)) & 0xff));
  };
  u32(kGlbMagic);
  u32(2);
  u32(length);
  u32(uint32_t(text.size()));
  u32(kChunkJson);
  glb += text;
  glb.append(bytes, rest, std::string::npos);
  return glb;
}

tinygltf::Model decode(const std::string& bytes, bool binary, const fs::path& folder,
                       const std::string& file) {
  FolderGuard guard{folder};
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks(
      {&guardedFileExists, &guardedExpandFilePath, &guardedReadWholeFile, &refuseWrite, &guard});
  loader.SetImageLoader(&loadImageWithinLimits, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  auto data = reinterpret_cast<const unsigned char*>(bytes.data());
  // Section checks are off: the first pass has already checked what glint needs.
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, unsigned(bytes.size()),
                                              folder.string(), 0)
                : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                             unsigned(bytes.size()), folder.string(), 0);
  } catch (const std::exception& e) {
    err = e.what();  // tinygltf's JSON library may throw on input the first pass let through
  }
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    throw SceneError({file, ""},
                     "cannot decode glTF: " + (err.empty() ? std::string("unknown error") : err));
  }
  return model;
}

// ---------------------------------------------------------------------------------------------
// Accessors
// ---------------------------------------------------------------------------------------------

double readComponent(const uint8_t* p, int componentType, bool normalized) {
  switch (componentType) {
    case gltf::kByte: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case gltf::kUnsignedByte:
      return normalized ? *p / 255.0 : *p;
    case gltf::kShort: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case gltf::kUnsignedShort: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case gltf::kUnsignedInt: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

class AccessorReader {
 public:
  AccessorReader(const Document& doc, const tinygltf::Model& model) : doc_(doc), model_(model) {}

  // The accessor's elements as `components` doubles each (normalized integers mapped to
  // [0, 1] or [-1, 1]), with sparse substitution applied. Byte ranges were checked against the
  // declared lengths in the first pass; here they are checked against the decoded data.
  std::vector<double> read(int index) const {
    if (auto it = decoded_.find(index); it != decoded_.end()) return it->second;
    const Accessor& a = doc_.accessors[size_t(index)];
    size_t n = size_t(a.components);
    std::vector<double> out(a.count * n, 0.0);
    size_t elem = gltf::elementSize(a);
    if (a.bufferView >= 0) {
      size_t stride = doc_.bufferViews[size_t(a.bufferView)].byteStride;
      if (stride == 0) stride = elem;
      const uint8_t* base =
          viewData(a.bufferView, a.byteOffset, stride * (a.count - 1) + elem, a.where);
      for (size_t i = 0; i < a.count; ++i) readElement(a, base + i * stride, &out[i * n]);
    }
    if (a.sparse) {
      const gltf::Sparse& s = *a.sparse;
      size_t indexSize = gltf::componentSize(s.indicesComponentType);
      const uint8_t* indices =
          viewData(s.indicesView, s.indicesOffset, indexSize * s.count, s.where);
      const uint8_t* values = viewData(s.valuesView, s.valuesOffset, elem * s.count, s.where);
      double previous = -1;
      for (size_t k = 0; k < s.count; ++k) {
        double i = readComponent(indices + k * indexSize, s.indicesComponentType, false);
        if (i <= previous || i >= double(a.count))
          throw SceneError(
              s.where.child("indices"),
              "sparse index " + std::to_string(uint64_t(i)) + " at position " + std::to_string(k) +
                  (i >= double(a.count) ? " is out of range (count " + std::to_string(a.count) + ")"
                                        : " is not greater than the previous one"));
        previous = i;
        readElement(a, values + k * elem, &out[size_t(i) * n]);
      }
    }
    return out;
  }

 private:
  void readElement(const Accessor& a, const uint8_t* p, double* out) const {
    size_t c = gltf::componentSize(a.componentType);
    int rows = a.type == "MAT2" ? 2 : a.type == "MAT3" ? 3 : a.type == "MAT4" ? 4 : a.components;
    int columns = a.components / rows;
    size_t columnBytes = a.components == rows ? 0 : (rows * c + 3) / 4 * 4;
    for (int col = 0; col < columns; ++col)
      for (int r = 0; r < rows; ++r)
        out[col * rows + r] =
            readComponent(p + col * columnBytes + size_t(r) * c, a.componentType, a.normalized);
  }

 public:
  // Values decoded from a compressed primitive (KHR_draco_mesh_compression) stand in for the
  // accessors they describe until the next call.
  void setDecoded(std::map<int, std::vector<double>> decoded) { decoded_ = std::move(decoded); }
  // The bytes of a buffer view.
  const uint8_t* view(int index, size_t* size, const SourceLocation& where) const {
    *size = doc_.bufferViews[size_t(index)].byteLength;
    return viewData(index, 0, *size, where);
  }

 private:
  const uint8_t* viewData(int view, size_t offset, size_t bytes,
                          const SourceLocation& where) const {
    const gltf::BufferView& v = doc_.bufferViews[size_t(view)];
    if (v.meshopt) {  // EXT_meshopt_compression: decoded once, on first use
      auto it = decodedViews_.find(view);
      if (it == decodedViews_.end()) {
        const gltf::BufferView::Meshopt& m = *v.meshopt;
        const std::vector<unsigned char>& source = model_.buffers[size_t(m.buffer)].data;
        if (m.byteOffset + m.byteLength > source.size())
          throw SceneError(m.where, "compressed bytes lie outside the decoded buffer " +
                                        std::to_string(m.buffer) + " (" +
                                        std::to_string(source.size()) + " bytes)");
        it = decodedViews_
                 .emplace(view,
                          gltf::decodeMeshoptView(v, source.data() + m.byteOffset, m.byteLength))
                 .first;
      }
      if (offset + bytes > it->second.size())
        throw SceneError(where, "data of bufferView " + std::to_string(view) +
                                    " lies outside its decompressed " +
                                    std::to_string(it->second.size()) + " bytes");
      return it->second.data() + offset;
    }
    const std::vector<unsigned char>& data = model_.buffers[size_t(v.buffer)].data;
    if (v.byteOffset + offset + bytes > data.size())
      throw SceneError(where, "data of bufferView " + std::to_string(view) +
                                  " lies outside the decoded buffer " + std::to_string(v.buffer) +
                                  " (" + std::to_string(data.size()) + " bytes)");
    return data.data() + v.byteOffset + offset;
  }

  const Document& doc_;
  const tinygltf::Model& model_;
  std::map<int, std::vector<double>> decoded_;
  mutable std::map<int, std::vector<uint8_t>> decodedViews_;  // EXT_meshopt_compression
};

// ---------------------------------------------------------------------------------------------
// Images, textures, materials
// ---------------------------------------------------------------------------------------------

ImageDesc convertImage(const gltf::Image& im, const tinygltf::Image& file, size_t index) {
  ImageDesc d;
  d.name = im.uri.empty() || isDataUri(im.uri) ? "image " + std::to_string(index) : im.uri;
  d.encoded = std::make_shared<const std::string>(file.image.begin(), file.image.end());
  try {
    const EncodedImageInfo info = oiio::plugin().probeEncodedImage(*d.encoded);
    d.width = info.width, d.height = info.height, d.channels = info.channels, d.bits = info.bits;
  } catch (const FailureError&) {
    throw;  // not the file's fault (the OpenImageIO plugin is missing): exit code 1
  } catch (const std::exception& e) {
    throw SceneError(im.where, e.what());
  }
  d.where = im.where;
  return d;
}

// ---------------------------------------------------------------------------------------------
// The loader
// ---------------------------------------------------------------------------------------------

const char* modeName(int mode) {
  static const char* names[] = {"POINTS",    "LINES",          "LINE_LOOP",   "LINE_STRIP",
                                "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};
  return names[mode];
}

class Loader {
 public:
  Loader(const Document& doc, const tinygltf::Model& model, SceneDescription* scene)
      : doc_(doc), model_(model), reader_(doc, model), scene_(scene) {
    imageBase_ = int(scene->images.size());
    textureBase_ = int(scene->textures.size());
    materialBase_ = int(scene->materials.size());
  }

  void run(const Transform& rootTransform) {
    for (const std::string& w : doc_.warnings) scene_->warnings.push_back(w);
    for (const std::string& e : doc_.extensionsUsed) quantized_ |= e == "KHR_mesh_quantization";
    for (const std::string& v : doc_.variants)
      if (std::find(scene_->variants.begin(), scene_->variants.end(), v) == scene_->variants.end())
        scene_->variants.push_back(v);
    for (size_t i = 0; i < doc_.images.size(); ++i)
      scene_->images.push_back(convertImage(doc_.images[i], model_.images.at(i), i));
    for (const gltf::Texture& t : doc_.textures) {
      TextureDesc d;
      d.image = imageBase_ + t.source;
      if (t.sampler >= 0) {
        const gltf::Sampler& s = doc_.samplers[size_t(t.sampler)];
        d.wrapS = s.wrapS, d.wrapT = s.wrapT;
        d.nearest = s.magFilter == 9728;
      }
      d.where = t.where;
      scene_->textures.push_back(d);
    }
    for (const gltf::Material& m : doc_.materials) {
      MaterialDesc d;
      d.name = m.name;
      // KHR_materials_unlit: the base colour (factor, texture, vertex colours, alpha) alone.
      d.type = m.unlit ? MaterialType::Unlit : MaterialType::Pbr;
      d.baseColor = {m.baseColorFactor.x, m.baseColorFactor.y, m.baseColorFactor.z};
      d.opacity = m.baseColorFactor.w;
      // A texture reference: the file's texture, or a copy of it that reads TEXCOORD_1 and/or
      // applies KHR_texture_transform's UV transform (one copy per distinct use; the image is
      // shared). Sets above 1 were warned about and read TEXCOORD_0.
      auto texture = [&](const gltf::TextureRef& r) {
        if (r.index < 0) return -1;
        const int base = textureBase_ + r.index;
        const int uvSet = r.texCoord == 1 ? 1 : 0;
        if (!r.transformed && uvSet == 0) return base;
        const auto key =
            std::make_tuple(base, uvSet, r.offset.x, r.offset.y, r.scale.x, r.scale.y, r.rotation);
        if (auto it = transformedTextures_.find(key); it != transformedTextures_.end())
          return it->second;
        TextureDesc t = scene_->textures[size_t(base)];
        t.name += r.transformed ? " (KHR_texture_transform)" : " (TEXCOORD_1)";
        t.mapping.scale = {r.scale.x, r.scale.y, 1};
        t.mapping.offset = {r.offset.x, r.offset.y, 0};
        t.mapping.uvRotation = r.rotation;
        t.mapping.uvSet = uvSet;
        t.where =
            r.transformed ? r.where.child("extensions").child("KHR_texture_transform") : r.where;
        scene_->textures.push_back(t);
        return transformedTextures_[key] = int(scene_->textures.size() - 1);
      };
      d.baseColorTexture = texture(m.baseColorTexture);
      d.metallic = m.metallic, d.roughness = m.roughness;
      d.metallicRoughnessTexture = texture(m.metallicRoughnessTexture);
      d.normalTexture = texture(m.normalTexture);
      d.normalScale = m.normalScale;
      d.alphaMode = m.alphaMode == "MASK"    ? AlphaModeDesc::Mask
                    : m.alphaMode == "BLEND" ? AlphaModeDesc::Blend
                                             : AlphaModeDesc::Opaque;
      d.alphaCutoff = m.alphaCutoff;
      d.transmission = m.transmission;
      d.transmissionTexture = texture(m.transmissionTexture);
      d.ior = m.ior;
      d.emissive = m.emissiveFactor * m.emissiveStrength;
      d.emissiveTexture = texture(m.emissiveTexture);
      d.doubleSided = m.doubleSided;
      // Without KHR_materials_volume's thickness, glTF transmission is a thin sheet.
      d.thinWalled = !(m.layers.thickness > 0);
      d.layers = m.layers;
      const gltf::Material::LayerTextures& lt = m.layerTextures;
      MaterialLayersDesc& l = d.layers;
      l.specularTexture = texture(lt.specular);
      l.specularColorTexture = texture(lt.specularColor);
      l.clearcoatTexture = texture(lt.clearcoat);
      l.clearcoatRoughnessTexture = texture(lt.clearcoatRoughness);
      l.clearcoatNormalTexture = texture(lt.clearcoatNormal);
      l.sheenColorTexture = texture(lt.sheenColor);
      l.sheenRoughnessTexture = texture(lt.sheenRoughness);
      l.diffuseTransmissionTexture = texture(lt.diffuseTransmission);
      l.diffuseTransmissionColorTexture = texture(lt.diffuseTransmissionColor);
      l.iridescenceTexture = texture(lt.iridescence);
      l.iridescenceThicknessTexture = texture(lt.iridescenceThickness);
      l.anisotropyTexture = texture(lt.anisotropy);
      d.where = m.where;
      scene_->materials.push_back(d);
    }

    std::vector<int> roots;
    if (doc_.scene >= 0) {
      roots = doc_.scenes[size_t(doc_.scene)].nodes;
    } else if (!doc_.scenes.empty()) {
      roots = doc_.scenes[0].nodes;
    } else {
      // No scenes: every node without a parent is a root.
      std::vector<bool> isChild(doc_.nodes.size(), false);
      for (const gltf::Node& n : doc_.nodes)
        for (int c : n.children) isChild[size_t(c)] = true;
      for (size_t i = 0; i < doc_.nodes.size(); ++i)
        if (!isChild[i]) roots.push_back(int(i));
    }
    readTracks();
    subtreeAnimated_.assign(doc_.nodes.size(), -1);
    nodeDesc_.assign(doc_.nodes.size(), -1);
    nodeWorld_.assign(doc_.nodes.size(), std::nullopt);
    rootTransform_ = rootTransform;
    for (int r : roots) visit(r, rootTransform, -1, false);
    resolveSkins();
  }

 private:
  // ---- animations ---------------------------------------------------------------------------

  struct NodeTracks {
    Track<Vec3f> translation, scale;
    Track<Quaternion> rotation;
  };

  // Keyframe times of sampler `s`: finite, >= 0 and strictly increasing (glTF 2.0).
  std::vector<float> readTimes(const gltf::AnimationSampler& s) const {
    std::vector<double> v = reader_.read(s.input);
    std::vector<float> times(v.size());
    SourceLocation at = s.where.child("input");
    for (size_t i = 0; i < v.size(); ++i) {
      times[i] = float(v[i]);
      if (!std::isfinite(times[i]) || times[i] < 0)
        throw SceneError(at, "accessor " + std::to_string(s.input) + ": key " + std::to_string(i) +
                                 " has time " + std::to_string(v[i]) +
                                 "; times must be finite and >= 0");
      if (i > 0 && !(times[i] > times[i - 1]))
        throw SceneError(at, "accessor " + std::to_string(s.input) + ": key " + std::to_string(i) +
                                 " at time " + std::to_string(times[i]) +
                                 " does not come after key " + std::to_string(i - 1) + " at " +
                                 std::to_string(times[i - 1]) + "; times must increase strictly");
    }
    return times;
  }

  template <class T>
  void fillTrack(Track<T>* track, const gltf::AnimationSampler& s, const gltf::AnimationChannel& c,
                 gltf::AnimationPath path) {
    track->interpolation = s.interpolation;
    track->times = readTimes(s);
    track->where = c.where;
    std::vector<double> v = reader_.read(s.output);
    const Accessor& out = doc_.accessors[size_t(s.output)];
    size_t n = out.count;
    bool cubic = s.interpolation == Interpolation::CubicSpline;
    SourceLocation at = s.where.child("output");
    for (size_t i = 0; i < n; ++i) {
      // Only key values (not CUBICSPLINE tangents) must be unit quaternions and non-zero scales.
      bool isValue = !cubic || i % 3 == 1;
      std::string which =
          "element " + std::to_string(i) + " of accessor " + std::to_string(s.output);
      if constexpr (std::is_same_v<T, Quaternion>) {
        Quaternion q{float(v[4 * i]), float(v[4 * i + 1]), float(v[4 * i + 2]),
                     float(v[4 * i + 3])};
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z) ||
            !std::isfinite(q.w))
          throw SceneError(at, which + " is not finite");
        if (isValue) {
          if (!(dot(q, q) > 1e-12f)) throw SceneError(at, which + " is a zero quaternion");
          q = normalize(q);
        }
        track->values.push_back(q);
      } else {
        Vec3f x{float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2])};
        if (!isFinite(x)) throw SceneError(at, which + " is not finite");
        if (isValue && path == gltf::AnimationPath::Scale && (x.x == 0 || x.y == 0 || x.z == 0))
          throw SceneError(at, which +
                                   " is a scale with a zero component, which glint cannot "
                                   "place (the node matrix would not be invertible)");
        track->values.push_back(x);
      }
    }
  }

  // A weights channel as one track per morph target: glTF interleaves the targets within each
  // key (and, for CUBICSPLINE, in-tangents, values, out-tangents each as a run of targets).
  std::vector<Track<float>> readWeightTracks(const gltf::AnimationSampler& s,
                                             const gltf::AnimationChannel& c) {
    const size_t targets = doc_.meshes[size_t(doc_.nodes[size_t(c.node)].mesh)].targetCount;
    std::vector<Track<float>> tracks(targets);
    const std::vector<float> times = readTimes(s);
    const std::vector<double> v = reader_.read(s.output);
    const bool cubic = s.interpolation == Interpolation::CubicSpline;
    const size_t perKey = cubic ? 3 : 1;
    for (size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i]))
        throw SceneError(s.where.child("output"), "element " + std::to_string(i) + " of accessor " +
                                                      std::to_string(s.output) + " is not finite");
    for (size_t t = 0; t < targets; ++t) {
      tracks[t].interpolation = s.interpolation;
      tracks[t].times = times;
      tracks[t].where = c.where;
      for (size_t k = 0; k < times.size(); ++k)
        for (size_t part = 0; part < perKey; ++part)
          tracks[t].values.push_back(float(v[(k * perKey + part) * targets + t]));
    }
    return tracks;
  }

  // Every animation in the file plays at once, on one clock: glTF files usually hold one
  // animation, and a viewer's "play all" is the only choice that needs no name. When two
  // animations drive the same property, the first one wins (with a warning).
  void readTracks() {
    for (const gltf::Animation& anim : doc_.animations) {
      for (const gltf::AnimationChannel& c : anim.channels) {
        if (c.node < 0) continue;
        const gltf::AnimationSampler& s = anim.samplers[size_t(c.sampler)];
        if (c.path == gltf::AnimationPath::Weights) {
          const gltf::Node& node = doc_.nodes[size_t(c.node)];
          if (node.mesh < 0 || doc_.meshes[size_t(node.mesh)].targetCount == 0) {
            scene_->warnings.push_back(c.where.str() + ": node " + std::to_string(c.node) +
                                       " has no mesh with morph targets; its weights channel "
                                       "is ignored");
            continue;
          }
          if (weightTracks_.count(c.node)) {
            scene_->warnings.push_back(c.where.str() + ": node " + std::to_string(c.node) +
                                       " weights are already animated by an earlier "
                                       "animation; ignored");
            continue;
          }
          weightTracks_[c.node] = readWeightTracks(s, c);
          continue;
        }
        NodeTracks& t = tracks_[c.node];
        bool taken = c.path == gltf::AnimationPath::Translation ? !t.translation.empty()
                     : c.path == gltf::AnimationPath::Rotation  ? !t.rotation.empty()
                                                                : !t.scale.empty();
        if (taken) {
          scene_->warnings.push_back(c.where.str() + ": node " + std::to_string(c.node) +
                                     " is already animated by an earlier animation; ignored");
          continue;
        }
        if (c.path == gltf::AnimationPath::Translation)
          fillTrack(&t.translation, s, c, c.path);
        else if (c.path == gltf::AnimationPath::Rotation)
          fillTrack(&t.rotation, s, c, c.path);
        else
          fillTrack(&t.scale, s, c, c.path);
      }
    }
  }

  // Whether node `index` or a node below it has tracks (memoised; the graph is a forest).
  bool subtreeAnimated(int index) {
    int& memo = subtreeAnimated_[size_t(index)];
    if (memo >= 0) return memo;
    bool any = tracks_.count(index) > 0;
    for (int c : doc_.nodes[size_t(index)].children) any = subtreeAnimated(c) || any;
    memo = any;
    return any;
  }

  // The NodeDesc of the glTF root transform, made on first use (-1 when it is the identity).
  int rootNode() {
    if (rootTransform_.isIdentity()) return -1;
    if (rootNode_ < 0) {
      NodeDesc root;
      root.name = "glTF root transform";
      root.hasMatrix = true;
      root.matrix = rootTransform_;
      root.where = SourceLocation{doc_.file, ""};
      scene_->nodes.push_back(root);
      rootNode_ = int(scene_->nodes.size()) - 1;
    }
    return rootNode_;
  }

  // ---- the node walk ------------------------------------------------------------------------

  // The node graph was checked to be a forest, so recursion terminates. Nodes whose world
  // transform can change (animated, below an animated node, or above one) are kept as
  // NodeDescs; `parentDesc` is the parent's (-1 when it has none) and `moving` says whether
  // the parent moves.
  void visit(int index, const Transform& parent, int parentDesc, bool moving) {
    const gltf::Node& node = doc_.nodes[size_t(index)];
    std::string nodeName = node.name.empty() ? "node " + std::to_string(index) : node.name;
    Transform world = parent * node.local;
    int desc = -1;
    if (moving || subtreeAnimated(index)) {
      NodeDesc d;
      d.name = nodeName;
      d.parent = parentDesc >= 0 ? parentDesc : rootNode();
      d.hasMatrix = node.hasMatrix;
      d.matrix = node.local;
      d.translation = node.translation;
      d.rotation = node.rotation;
      d.scale = node.scale;
      if (auto it = tracks_.find(index); it != tracks_.end()) {
        d.translationTrack = it->second.translation;
        d.rotationTrack = it->second.rotation;
        d.scaleTrack = it->second.scale;
      }
      d.where = node.where;
      scene_->nodes.push_back(d);
      desc = int(scene_->nodes.size()) - 1;
      moving = isAnimated(scene_->nodes, desc);
      // The placement at time 0: a channel's first value, else the rest value.
      world = worldFromNode(scene_->nodes, desc, 0.0);
    }
    int transformNode = moving ? desc : -1;
    nodeDesc_[size_t(index)] = transformNode;
    nodeWorld_[size_t(index)] = world;
    if (node.mesh >= 0) {
      const std::vector<int>& meshes = meshDescs(node.mesh);
      const gltf::Mesh& gm = doc_.meshes[size_t(node.mesh)];
      // EXT_mesh_gpu_instancing: one placement per instance, in the node's frame.
      const std::vector<Transform> copies = instancePlacements(node);
      for (size_t copy = 0; copy < std::max<size_t>(copies.size(), 1); ++copy) {
        for (size_t p = 0; p < meshes.size(); ++p) {
          const int m = meshes[p];
          if (m < 0) continue;
          InstanceDesc inst;
          inst.mesh = m;
          inst.worldFromObject = world;
          inst.transformNode = transformNode;
          if (!copies.empty() && node.skin < 0) {
            inst.worldFromObject = world * copies[copy];
            inst.nodeFromObject = copies[copy];
          }
          inst.node = nodeName;
          inst.where = node.where;
          inst.morphWeights = node.weights;
          if (auto it = weightTracks_.find(index); it != weightTracks_.end())
            inst.weightTracks = it->second;
          const MeshDesc& md = scene_->meshes[size_t(m)];
          if (node.skin >= 0 && !md.joints.empty()) {
            // glTF: the skin places the vertices; the skinned node's own transform is ignored.
            const gltf::Skin& skin = doc_.skins[size_t(node.skin)];
            for (size_t v = 0; v < md.joints.size(); ++v)
              for (int k = 0; k < 4; ++k)
                if (md.jointWeights[v][k] > 0 && md.joints[v][size_t(k)] >= skin.joints.size())
                  throw SceneError(gm.primitives[p].where.child("attributes").child("JOINTS_0"),
                                   "vertex " + std::to_string(v) + " names joint " +
                                       std::to_string(md.joints[v][size_t(k)]) + " but skin " +
                                       std::to_string(node.skin) + " (" +
                                       node.where.child("skin").pointer + ") has " +
                                       std::to_string(skin.joints.size()) + " joints");
            inst.worldFromObject = Transform();
            inst.transformNode = -1;
            pendingSkins_.emplace_back(scene_->instances.size(), node.skin);
          } else if (node.skin < 0 && !md.joints.empty()) {
            scene_->warnings.push_back(gm.primitives[p].where.str() +
                                       ": JOINTS_0/WEIGHTS_0 without a skin on node " +
                                       std::to_string(index) + "; drawn unskinned");
          }
          scene_->instances.push_back(inst);
        }
      }
    }
    if (node.camera >= 0) {
      CameraDesc c = doc_.cameras[size_t(node.camera)];
      if (c.name.empty())
        c.name = node.name.empty() ? "camera " + std::to_string(node.camera) : node.name;
      c.worldFromCamera = world;
      c.transformNode = transformNode;
      scene_->cameras.push_back(c);
    }
    if (node.light >= 0) {
      LightDesc l = doc_.lights[size_t(node.light)];
      if (l.name.empty())
        l.name = node.name.empty() ? "light " + std::to_string(node.light) : node.name;
      l.worldFromLight = world;
      l.transformNode = transformNode;
      scene_->lights.push_back(l);
    }
    for (int c : node.children) visit(c, world, desc, moving);
  }

  // The per-instance placements of an EXT_mesh_gpu_instancing node (T · R · S of each), or
  // none. Rotations are normalised; non-finite values and zero scales are errors.
  std::vector<Transform> instancePlacements(const gltf::Node& node) {
    std::vector<Transform> out;
    if (node.instanceCount == 0) return out;
    const SourceLocation attrs =
        node.where.child("extensions").child("EXT_mesh_gpu_instancing").child("attributes");
    if (node.skin >= 0) {
      scene_->warnings.push_back(attrs.str() +
                                 ": EXT_mesh_gpu_instancing on a skinned node is ignored (the "
                                 "skin places the mesh once)");
      return out;
    }
    std::vector<double> t, r, sc;
    if (node.instanceTranslation >= 0) t = reader_.read(node.instanceTranslation);
    if (node.instanceRotation >= 0) r = reader_.read(node.instanceRotation);
    if (node.instanceScale >= 0) sc = reader_.read(node.instanceScale);
    out.reserve(node.instanceCount);
    for (size_t i = 0; i < node.instanceCount; ++i) {
      Vec3f translation{0, 0, 0}, scale{1, 1, 1};
      Quaternion rotation;
      if (!t.empty()) translation = {float(t[3 * i]), float(t[3 * i + 1]), float(t[3 * i + 2])};
      if (!sc.empty()) scale = {float(sc[3 * i]), float(sc[3 * i + 1]), float(sc[3 * i + 2])};
      if (!r.empty()) {
        rotation = {float(r[4 * i]), float(r[4 * i + 1]), float(r[4 * i + 2]), float(r[4 * i + 3])};
        if (!(dot(rotation, rotation) > 1e-12f) || !std::isfinite(dot(rotation, rotation)))
          throw SceneError(attrs.child("ROTATION"),
                           "instance " + std::to_string(i) + " has a zero or non-finite rotation");
        rotation = normalize(rotation);
      }
      if (!isFinite(translation))
        throw SceneError(attrs.child("TRANSLATION"),
                         "instance " + std::to_string(i) + " has a non-finite translation");
      if (!isFinite(scale) || scale.x == 0 || scale.y == 0 || scale.z == 0)
        throw SceneError(attrs.child("SCALE"),
                         "instance " + std::to_string(i) + " has a zero or non-finite scale");
      out.push_back(Transform::translate(translation) * toTransform(rotation) *
                    Transform::scale(scale));
    }
    return out;
  }

  // The world placement of glTF node `index` at rest, for joints outside the scene walked.
  Transform restWorld(int index) {
    if (nodeWorld_[size_t(index)]) return *nodeWorld_[size_t(index)];
    if (parent_.empty()) {
      parent_.assign(doc_.nodes.size(), -1);
      for (size_t i = 0; i < doc_.nodes.size(); ++i)
        for (int c : doc_.nodes[i].children) parent_[size_t(c)] = int(i);
    }
    const int p = parent_[size_t(index)];
    return (p >= 0 ? restWorld(p) : rootTransform_) * doc_.nodes[size_t(index)].local;
  }

  // SkinDescs for the skins skinned instances use (one per glTF skin), their joints placed by
  // the nodes the walk made (animated) or at rest.
  void resolveSkins() {
    std::map<int, int> skinDesc;  // glTF skin -> SceneDescription::skins index
    for (auto [instance, skin] : pendingSkins_) {
      auto it = skinDesc.find(skin);
      if (it == skinDesc.end()) {
        const gltf::Skin& gs = doc_.skins[size_t(skin)];
        SkinDesc d;
        d.name = "skin " + std::to_string(skin);
        d.where = gs.where;
        std::vector<double> ibm;
        if (gs.inverseBindMatrices >= 0) ibm = reader_.read(gs.inverseBindMatrices);
        for (size_t j = 0; j < gs.joints.size(); ++j) {
          const int node = gs.joints[j];
          d.joints.push_back({nodeDesc_[size_t(node)], restWorld(node)});
          Transform inverseBind;
          if (!ibm.empty()) {
            float f[16];
            for (int k = 0; k < 16; ++k) f[k] = float(ibm[16 * j + size_t(k)]);
            Mat4 m = Mat4::fromColumnMajor(f), inv;
            if (!invert(m, &inv))
              throw SceneError(gs.where.child("inverseBindMatrices"),
                               "matrix " + std::to_string(j) + " of accessor " +
                                   std::to_string(gs.inverseBindMatrices) +
                                   " is not finite and invertible");
            inverseBind = Transform(m, inv);
          }
          d.inverseBind.push_back(inverseBind);
        }
        scene_->skins.push_back(std::move(d));
        it = skinDesc.emplace(skin, int(scene_->skins.size()) - 1).first;
      }
      scene_->instances[instance].skin = it->second;
    }
  }

  // The MeshDesc indices of glTF mesh `m`'s primitives (-1 for skipped ones), converted on
  // first use so that every node using the mesh shares them.
  const std::vector<int>& meshDescs(int m) {
    auto it = converted_.find(m);
    if (it != converted_.end()) return it->second;
    const gltf::Mesh& mesh = doc_.meshes[size_t(m)];
    std::vector<int> ids;
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      std::string name = mesh.name;
      if (mesh.primitives.size() > 1) name += " (primitive " + std::to_string(p) + ")";
      ids.push_back(convertPrimitive(mesh.primitives[p], name, mesh.weights));
    }
    return converted_[m] = ids;
  }

  // What component types an attribute may have: core glTF allows FLOAT (and normalized
  // UNSIGNED_BYTE/SHORT for texture coordinates, colours and weights); KHR_mesh_quantization
  // adds integer positions and displacements, normalized BYTE/SHORT directions, and any 8- or
  // 16-bit texture coordinates.
  enum class Kind { Position, Direction, TexCoord, Color };

  bool componentAllowed(const Accessor& a, Kind kind) const {
    const int c = a.componentType;
    if (c == gltf::kFloat) return true;
    const bool unsigned8or16 = c == gltf::kUnsignedByte || c == gltf::kUnsignedShort;
    const bool signed8or16 = c == gltf::kByte || c == gltf::kShort;
    if ((kind == Kind::TexCoord || kind == Kind::Color) && a.normalized && unsigned8or16)
      return true;
    if (!quantized_) return false;
    switch (kind) {
      case Kind::Position:
        return unsigned8or16 || signed8or16;
      case Kind::Direction:
        return a.normalized && signed8or16;
      case Kind::TexCoord:
        return unsigned8or16 || signed8or16;
      case Kind::Color:
        return false;
    }
    return false;
  }

  std::string allowedComponents(Kind kind) const {
    std::string core = kind == Kind::TexCoord || kind == Kind::Color
                           ? "FLOAT or normalized UNSIGNED_BYTE/UNSIGNED_SHORT"
                           : "FLOAT";
    if (kind == Kind::Color) return core;
    if (!quantized_) return core + " (other types need KHR_mesh_quantization)";
    switch (kind) {
      case Kind::Position:
        return "FLOAT, BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT";
      case Kind::Direction:
        return "FLOAT or normalized BYTE/SHORT";
      default:
        return "FLOAT, BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT";
    }
  }

  // Checks that accessor `index`, used as `attribute` at `where`, has an allowed layout.
  const Accessor& attribute(int index, const SourceLocation& where, const std::string& attribute,
                            std::initializer_list<const char*> types, Kind kind) const {
    const Accessor& a = doc_.accessors[size_t(index)];
    bool typeOk = false;
    for (const char* t : types) typeOk |= a.type == t;
    if (!typeOk || !componentAllowed(a, kind)) {
      std::string want;
      for (const char* t : types) want += std::string(want.empty() ? "" : " or ") + t;
      throw SceneError(where, "accessor " + std::to_string(index) + " is " + a.type + " of " +
                                  (a.normalized ? "normalized " : "") +
                                  gltf::componentTypeName(a.componentType) + "; " + attribute +
                                  " must be " + want + " of " + allowedComponents(kind));
    }
    return a;
  }
  const Accessor& attribute(int index, const gltf::Primitive& p, const std::string& name,
                            std::initializer_list<const char*> types, Kind kind) const {
    return attribute(index, p.where.child("attributes").child(name), name, types, kind);
  }

  // JOINTS_0 (VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT) and WEIGHTS_0 (VEC4 of FLOAT or
  // normalized UNSIGNED_BYTE/SHORT): finite, non-negative weights; joint indices are checked
  // against the skin of each node that uses the mesh.
  void readSkinning(const gltf::Primitive& p, size_t n, MeshDesc* mesh) {
    const SourceLocation attrs = p.where.child("attributes");
    const Accessor& ja = doc_.accessors[size_t(p.joints0)];
    if (ja.type != "VEC4" || ja.normalized ||
        (ja.componentType != gltf::kUnsignedByte && ja.componentType != gltf::kUnsignedShort))
      throw SceneError(attrs.child("JOINTS_0"),
                       "accessor " + std::to_string(p.joints0) + " is " + ja.type + " of " +
                           gltf::componentTypeName(ja.componentType) +
                           "; JOINTS_0 must be VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT");
    const Accessor& wa = attribute(p.weights0, p, "WEIGHTS_0", {"VEC4"}, Kind::Color);
    for (auto [index, what] : {std::pair{p.joints0, "JOINTS_0"}, {p.weights0, "WEIGHTS_0"}})
      if (doc_.accessors[size_t(index)].count != n)
        throw SceneError(attrs.child(what),
                         "accessor " + std::to_string(index) + " has " +
                             std::to_string(doc_.accessors[size_t(index)].count) +
                             " elements but POSITION has " + std::to_string(n));
    std::vector<double> j = reader_.read(p.joints0), w = reader_.read(p.weights0);
    mesh->joints.resize(n);
    mesh->jointWeights.resize(n);
    for (size_t i = 0; i < n; ++i) {
      for (int k = 0; k < 4; ++k) {
        mesh->joints[i][size_t(k)] = uint16_t(j[4 * i + size_t(k)]);
        const double wk = w[4 * i + size_t(k)];
        if (!std::isfinite(wk) || wk < 0)
          throw SceneError(wa.where, "weight " + std::to_string(k) + " of vertex " +
                                         std::to_string(i) + " is " + std::to_string(wk) +
                                         "; skin weights must be finite and >= 0");
      }
      mesh->jointWeights[i] = {float(w[4 * i]), float(w[4 * i + 1]), float(w[4 * i + 2]),
                               float(w[4 * i + 3])};
    }
    if (p.moreJoints)
      scene_->warnings.push_back(attrs.str() +
                                 ": JOINTS_1/WEIGHTS_1 ignored (glint blends the first four "
                                 "joints of each vertex)");
  }

  int convertPrimitive(const gltf::Primitive& p, const std::string& name,
                       const std::vector<float>& weights) {
    if (p.mode < gltf::kTriangles) {
      scene_->warnings.push_back(p.where.str() + ": " + modeName(p.mode) +
                                 " primitive skipped (only triangles are rendered)");
      return -1;
    }
    MeshDesc mesh;
    mesh.name = name;
    mesh.where = p.where;
    // A Draco-compressed primitive: its accessors read the decoded values (only while this
    // primitive is converted).
    struct ClearDecoded {
      AccessorReader& reader;
      ~ClearDecoded() { reader.setDecoded({}); }
    } clearDecoded{reader_};
    if (p.draco) {
      size_t size = 0;
      const uint8_t* bytes = reader_.view(p.draco->bufferView, &size, p.draco->where);
      reader_.setDecoded(gltf::decodeDracoPrimitive(bytes, size, p, doc_));
    }

    const Accessor& pa = attribute(p.position, p, "POSITION", {"VEC3"}, Kind::Position);
    std::vector<double> pos = reader_.read(p.position);
    size_t n = pa.count;
    mesh.positions.resize(n);
    for (size_t i = 0; i < n; ++i) {
      Vec3f v{float(pos[3 * i]), float(pos[3 * i + 1]), float(pos[3 * i + 2])};
      if (!isFinite(v))
        throw SceneError(pa.where, "position " + std::to_string(i) + " is not finite");
      mesh.positions[i] = v;
    }
    auto sameCount = [&](int index, const char* what) {
      const Accessor& a = doc_.accessors[size_t(index)];
      if (a.count != n)
        throw SceneError(p.where.child("attributes").child(what),
                         "accessor " + std::to_string(index) + " has " + std::to_string(a.count) +
                             " elements but POSITION has " + std::to_string(n));
    };
    if (p.normal >= 0) {
      const Accessor& na = attribute(p.normal, p, "NORMAL", {"VEC3"}, Kind::Direction);
      sameCount(p.normal, "NORMAL");
      std::vector<double> v = reader_.read(p.normal);
      mesh.normals.resize(n);
      for (size_t i = 0; i < n; ++i) {
        Vec3f nv{float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2])};
        if (!isFinite(nv))
          throw SceneError(na.where, "normal " + std::to_string(i) + " is not finite");
        float len = length(nv);
        if (!(len > 0) || !std::isfinite(len))
          throw SceneError(na.where, "normal " + std::to_string(i) + " has zero length");
        mesh.normals[i] = nv / len;
      }
    }
    if (p.tangent >= 0) {
      // xyz: the tangent (normalised), w: +-1, the handedness of the bitangent.
      const Accessor& ta = attribute(p.tangent, p, "TANGENT", {"VEC4"}, Kind::Direction);
      sameCount(p.tangent, "TANGENT");
      std::vector<double> v = reader_.read(p.tangent);
      mesh.tangents.resize(n);
      for (size_t i = 0; i < n; ++i) {
        Vec3f t{float(v[4 * i]), float(v[4 * i + 1]), float(v[4 * i + 2])};
        float w = float(v[4 * i + 3]);
        float len = length(t);
        if (!isFinite(t) || !std::isfinite(w) || !(len > 0) || !std::isfinite(len))
          throw SceneError(ta.where,
                           "tangent " + std::to_string(i) + " is not a finite, non-zero vector");
        t = t / len;
        mesh.tangents[i] = {t.x, t.y, t.z, w < 0 ? -1.0f : 1.0f};
      }
    }
    auto readUvs = [&](int accessor, const char* set, std::vector<Vec2f>* uvs) {
      if (accessor < 0) return;
      const Accessor& ta = attribute(accessor, p, set, {"VEC2"}, Kind::TexCoord);
      sameCount(accessor, set);
      std::vector<double> v = reader_.read(accessor);
      uvs->resize(n);
      for (size_t i = 0; i < n; ++i) {
        Vec2f uv{float(v[2 * i]), float(v[2 * i + 1])};
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
          throw SceneError(ta.where, "texture coordinate " + std::to_string(i) + " is not finite");
        (*uvs)[i] = uv;
      }
    };
    readUvs(p.texcoord0, "TEXCOORD_0", &mesh.uvs);
    readUvs(p.texcoord1, "TEXCOORD_1", &mesh.uvs1);
    if (p.color0 >= 0) {
      const Accessor& ca = attribute(p.color0, p, "COLOR_0", {"VEC3", "VEC4"}, Kind::Color);
      sameCount(p.color0, "COLOR_0");
      std::vector<double> v = reader_.read(p.color0);
      size_t c = size_t(ca.components);
      mesh.colors.resize(n);
      for (size_t i = 0; i < n; ++i) {
        Vec4f col{float(v[c * i]), float(v[c * i + 1]), float(v[c * i + 2]),
                  c == 4 ? float(v[c * i + 3]) : 1.0f};
        if (!std::isfinite(col.x) || !std::isfinite(col.y) || !std::isfinite(col.z) ||
            !std::isfinite(col.w))
          throw SceneError(ca.where, "color " + std::to_string(i) + " is not finite");
        mesh.colors[i] = col;
      }
    }

    if (p.joints0 >= 0) readSkinning(p, n, &mesh);
    for (size_t t = 0; t < p.targets.size(); ++t) {
      const gltf::MorphTarget& target = p.targets[t];
      MorphTargetDesc d;
      auto displacements = [&](int index, const char* what, std::vector<Vec3f>* out) {
        if (index < 0) return;
        SourceLocation at = target.where.child(what);
        const Accessor& a =
            attribute(index, at, std::string("a morph target's ") + what, {"VEC3"}, Kind::Position);
        if (a.count != n)
          throw SceneError(at, "accessor " + std::to_string(index) + " has " +
                                   std::to_string(a.count) + " elements but POSITION has " +
                                   std::to_string(n));
        std::vector<double> v = reader_.read(index);
        out->resize(n);
        for (size_t i = 0; i < n; ++i) {
          (*out)[i] = {float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2])};
          if (!isFinite((*out)[i]))
            throw SceneError(at, "displacement " + std::to_string(i) + " is not finite");
        }
      };
      displacements(target.position, "POSITION", &d.positions);
      displacements(target.normal, "NORMAL", &d.normals);
      displacements(target.tangent, "TANGENT", &d.tangents);
      mesh.targets.push_back(std::move(d));
    }
    mesh.weights = weights;

    // Vertex order: the index accessor, or 0..n-1 when there is none.
    std::vector<uint32_t> order;
    if (p.indices >= 0) {
      const Accessor& ia = doc_.accessors[size_t(p.indices)];
      if (ia.type != "SCALAR" || ia.normalized ||
          (ia.componentType != gltf::kUnsignedByte && ia.componentType != gltf::kUnsignedShort &&
           ia.componentType != gltf::kUnsignedInt))
        throw SceneError(
            p.where.child("indices"),
            "accessor " + std::to_string(p.indices) + " is " + ia.type + " of " +
                gltf::componentTypeName(ia.componentType) +
                "; indices must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
      std::vector<double> v = reader_.read(p.indices);
      order.resize(v.size());
      for (size_t i = 0; i < v.size(); ++i) {
        if (v[i] >= double(n))
          throw SceneError(p.where.child("indices"), "index " + std::to_string(uint64_t(v[i])) +
                                                         " out of range (" + std::to_string(n) +
                                                         " vertices)");
        order[i] = uint32_t(v[i]);
      }
    } else {
      order.resize(n);
      for (size_t i = 0; i < n; ++i) order[i] = uint32_t(i);
    }

    size_t m = order.size();
    if (p.mode == gltf::kTriangles) {
      if (m % 3)
        throw SceneError(p.where, "TRIANGLES primitive has " + std::to_string(m) +
                                      " vertices, not a multiple of 3");
      mesh.indices = std::move(order);
    } else if (p.mode == gltf::kTriangleStrip) {
      // glTF 2.0 §3.7.2.1: triangle i is (i, i+1+i%2, i+2-i%2), keeping the winding.
      for (size_t i = 0; i + 2 < m; ++i)
        mesh.indices.insert(mesh.indices.end(),
                            {order[i], order[i + 1 + i % 2], order[i + 2 - i % 2]});
    } else {  // TRIANGLE_FAN: triangle i is (i+1, i+2, 0).
      for (size_t i = 0; i + 2 < m; ++i)
        mesh.indices.insert(mesh.indices.end(), {order[i + 1], order[i + 2], order[0]});
    }
    if (mesh.indices.empty()) {
      scene_->warnings.push_back(p.where.str() + ": " + modeName(p.mode) +
                                 " primitive with fewer than 3 vertices skipped");
      return -1;
    }
    if (p.material >= 0) mesh.material = materialBase_ + p.material;
    for (const auto& [material, variants] : p.variantMappings)
      for (int v : variants)
        mesh.variantMaterials.emplace_back(doc_.variants[size_t(v)], materialBase_ + material);
    scene_->meshes.push_back(std::move(mesh));
    return int(scene_->meshes.size()) - 1;
  }

  const Document& doc_;
  const tinygltf::Model& model_;
  AccessorReader reader_;
  SceneDescription* scene_;
  int imageBase_ = 0, textureBase_ = 0, materialBase_ = 0;
  // Textures copied for TEXCOORD_1 or a KHR_texture_transform: (texture, uv set, offset,
  // scale, rotation) -> index.
  std::map<std::tuple<int, int, float, float, float, float, float>, int> transformedTextures_;
  std::map<int, std::vector<int>> converted_;
  std::map<int, NodeTracks> tracks_;                       // by glTF node index
  std::map<int, std::vector<Track<float>>> weightTracks_;  // by glTF node index
  bool quantized_ = false;  // KHR_mesh_quantization is used: integer attributes allowed
  // Per glTF node, from the walk: its animated placement (-1: static) and its world at time 0.
  std::vector<int> nodeDesc_;
  std::vector<std::optional<Transform>> nodeWorld_;
  std::vector<int> parent_;                           // made on first use by restWorld
  std::vector<std::pair<size_t, int>> pendingSkins_;  // (instance, glTF skin)
  std::vector<int> subtreeAnimated_;                  // -1 = not yet known
  Transform rootTransform_;
  int rootNode_ = -1;
};

}  // namespace

void loadGltf(const std::string& path, SceneDescription* scene, const Transform& rootTransform) {
  // A missing file is a SceneError naming it.
  loadGltfFromMemory(readTextFile(path), path, scene, rootTransform);
}

void loadGltfFromMemory(const std::string& bytes, const std::string& path, SceneDescription* scene,
                        const Transform& rootTransform) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(uint8_t(c)));
  bool binary = ext == ".glb" || hasGlbMagic(bytes);

  GlbChunks glb;
  if (binary) glb = parseGlb(bytes, path);
  nlohmann::json json = parseJson(binary ? glb.json : bytes, path);
  Document doc = gltf::readDocument(json, path);

  std::error_code ec;
  fs::path folder = canonicalOrSelf(fs::absolute(fs::path(path), ec).parent_path());
  checkSources(doc, folder, binary ? &glb : nullptr);

  tinygltf::Model model = decode(forTinygltf(bytes, binary, json, doc), binary, folder, path);
  if (model.buffers.size() != doc.buffers.size() || model.images.size() != doc.images.size())
    throw SceneError({path, ""}, "tinygltf decoded a different number of buffers or images");

  if (scene->file.empty()) scene->file = path;
  // On error leave `scene` as it was, so a caller that recovers sees no half-loaded file.
  size_t sizes[] = {scene->images.size(), scene->textures.size(),  scene->materials.size(),
                    scene->meshes.size(), scene->instances.size(), scene->cameras.size(),
                    scene->lights.size(), scene->warnings.size(),  scene->nodes.size()};
  try {
    Loader(doc, model, scene).run(rootTransform);
  } catch (...) {
    scene->images.resize(sizes[0]);
    scene->textures.resize(sizes[1]);
    scene->materials.resize(sizes[2]);
    scene->meshes.resize(sizes[3]);
    scene->instances.resize(sizes[4]);
    scene->cameras.resize(sizes[5]);
    scene->lights.resize(sizes[6]);
    scene->warnings.resize(sizes[7]);
    scene->nodes.resize(sizes[8]);
    throw;
  }
}

}  // namespace glint
