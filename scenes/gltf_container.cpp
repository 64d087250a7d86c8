// glint — the GLB container, URIs inside the scene folder, data URIs (see gltf_container.h).
#include "scenes/gltf_container.h"

#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>

#include "scenes/errors.h"

namespace glint::gltf {

namespace fs = std::filesystem;

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

Container readGlb(const std::string& bytes, const std::string& file) {
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
  Container glb;
  glb.binary = true;
  glb.json = std::string_view(bytes).substr(20, jsonLength);
  // The chunk is padded with spaces; tolerate NUL padding written by some exporters.
  while (!glb.json.empty() && glb.json.back() == '\0') glb.json.remove_suffix(1);
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
      glb.hasBin = true;
      glb.bin = std::string_view(bytes).substr(offset + 8, chunkLength);
    }
    offset += 8 + size_t(chunkLength);
  }
  return glb;
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

// The contents of the file a relative URI names, after checking that it stays inside `folder`
// (canonical). Throws at `where` (the "uri" property) otherwise, or when it cannot be read.
std::string readUri(const std::string& uri, const fs::path& folder, const SourceLocation& where) {
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
  std::ifstream in(path, std::ios::binary);
  if (!fs::is_regular_file(path, ec) || !in) throw SceneError(where, "cannot read '" + uri + "'");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw SceneError(where, "cannot read '" + uri + "'");
  return bytes;
}

// The data of one buffer or image source: a data URI or a file. `what` names the data URI's
// content in the message ("application/octet-stream").
std::string readSource(const std::string& uri, const fs::path& folder, const SourceLocation& where,
                       const char* what) {
  if (!isDataUri(uri)) return readUri(uri, folder, where);
  std::string bytes;
  if (!decodeDataUri(uri, &bytes))
    throw SceneError(
        where, std::string("cannot decode the data URI (data:") + what + ";base64,... expected)");
  return bytes;
}

// The value of base64 digit `c`, or -1.
int base64Digit(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Data URIs
// ---------------------------------------------------------------------------------------------

bool decodeDataUri(std::string_view uri, std::string* bytes) {
  if (uri.substr(0, 5) != "data:") return false;
  const size_t comma = uri.find(',');
  if (comma == std::string_view::npos) return false;
  // The media type and its parameters; glTF's binary data is always ";base64".
  const std::string_view header = uri.substr(5, comma - 5);
  if (header.size() < 7 || header.substr(header.size() - 7) != ";base64") return false;
  std::string_view data = uri.substr(comma + 1);
  // Padding: up to two '=' at the end, and then the digits fill whole groups of four.
  size_t padding = 0;
  while (!data.empty() && data.back() == '=' && padding < 2) data.remove_suffix(1), ++padding;
  if (data.size() % 4 == 1 || (padding > 0 && (data.size() + padding) % 4 != 0)) return false;
  bytes->clear();
  bytes->reserve(data.size() / 4 * 3 + 2);
  uint32_t group = 0;
  int bits = 0;
  for (char c : data) {
    const int d = base64Digit(c);
    if (d < 0) return false;
    group = group << 6 | uint32_t(d);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      bytes->push_back(char((group >> bits) & 0xff));
    }
  }
  return true;
}

Container readContainer(const std::string& bytes, const std::string& file) {
  std::string ext = fs::path(file).extension().string();
  for (char& c : ext) c = char(std::tolower(uint8_t(c)));
  if (ext == ".glb" || hasGlbMagic(bytes)) return readGlb(bytes, file);
  Container text;
  text.json = bytes;
  return text;
}

Payload readPayload(const Document& doc, const Container& file, const std::string& path) {
  std::error_code ec;
  const fs::path folder = canonicalOrSelf(fs::absolute(fs::path(path), ec).parent_path());
  Payload payload;
  for (size_t i = 0; i < doc.buffers.size(); ++i) {
    const Buffer& b = doc.buffers[i];
    if (b.uri.empty() && b.fallback) {  // EXT_meshopt_compression: no data needed
      payload.buffers.emplace_back();
      continue;
    }
    if (b.uri.empty()) {
      if (!file.binary || i != 0)
        throw SceneError(b.where, file.binary ? "only buffer 0 may refer to the GLB BIN chunk"
                                              : "missing 'uri' (only a .glb file may omit it)");
      if (file.bin.size() < b.byteLength)
        throw SceneError(b.where.child("byteLength"),
                         "byteLength is " + std::to_string(b.byteLength) +
                             " but the GLB BIN chunk has " + std::to_string(file.bin.size()) +
                             " bytes");
      payload.buffers.push_back(file.bin.substr(0, b.byteLength));
      continue;
    }
    auto data = std::make_unique<const std::string>(
        readSource(b.uri, folder, b.where.child("uri"), "application/octet-stream"));
    // The data must be the declared length exactly: a longer one hides a wrong byteLength.
    if (data->size() != b.byteLength)
      throw SceneError(
          b.where.child("byteLength"),
          "byteLength is " + std::to_string(b.byteLength) + " but " +
              (isDataUri(b.uri) ? std::string("the data URI holds ") : "'" + b.uri + "' has ") +
              std::to_string(data->size()) + " bytes");
    payload.buffers.push_back(*data);
    payload.owned.push_back(std::move(data));
  }
  for (const Image& im : doc.images) {
    if (!im.uri.empty()) {
      payload.images.push_back(std::make_shared<const std::string>(
          readSource(im.uri, folder, im.where.child("uri"), "image/png")));
      continue;
    }
    // An image in a buffer view (bounds against the declared byteLength were checked when
    // the document was read; here against the data).
    const BufferView& v = doc.bufferViews[size_t(im.bufferView)];
    const std::string_view buffer = payload.buffers[size_t(v.buffer)];
    if (v.byteOffset + v.byteLength > buffer.size())
      throw SceneError(im.where.child("bufferView"),
                       "bufferView " + std::to_string(im.bufferView) + " lies outside buffer " +
                           std::to_string(v.buffer) + " (" + std::to_string(buffer.size()) +
                           " bytes of data)");
    payload.images.push_back(
        std::make_shared<const std::string>(buffer.substr(v.byteOffset, v.byteLength)));
  }
  return payload;
}

}  // namespace glint::gltf
