// glint — glTF images, textures and materials (see gltf_materials.h).
#include "scenes/gltf_materials.h"

#include <map>
#include <string>
#include <tuple>

#include "image/oiio/plugin.h"
#include "materials/image_texture.h"
#include "scenes/errors.h"

namespace glint::gltf {

namespace {

// Images are decoded when a render scene is built, into as many pixels as the header states: a
// 100-byte PNG stating 60000 x 60000 pixels would ask for gigabytes (found by fuzzing). Larger
// than this is refused when the file is loaded.
constexpr uint64_t kMaxImagePixels = uint64_t(1) << 26;  // 8192 x 8192

void checkPixelCount(uint64_t width, uint64_t height, const SourceLocation& where) {
  if (width * height > kMaxImagePixels)
    throw SceneError(where, "the image is " + std::to_string(width) + " x " +
                                std::to_string(height) + " pixels: glint reads glTF images up to " +
                                std::to_string(kMaxImagePixels) + " pixels (8192 x 8192)");
}

// The big-endian 32-bit integer at b (PNG lengths and sizes).
uint64_t bigEndian32(const unsigned char* b) {
  return uint64_t(b[0]) << 24 | uint64_t(b[1]) << 16 | uint64_t(b[2]) << 8 | b[3];
}

// The width and height a PNG or JPEG header states; false for other data or a header too short.
bool imageHeaderSize(const unsigned char* b, size_t size, uint64_t* width, uint64_t* height) {
  const auto be32 = [&](size_t i) { return bigEndian32(b + i); };
  const auto be16 = [&](size_t i) { return uint64_t(b[i]) << 8 | b[i + 1]; };
  if (size >= 24 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G') {
    *width = be32(16), *height = be32(20);
    return true;
  }
  if (size < 4 || b[0] != 0xFF || b[1] != 0xD8) return false;
  for (size_t i = 2; i + 9 < size && b[i] == 0xFF;) {
    const uint64_t marker = b[i + 1];
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      *height = be16(i + 5), *width = be16(i + 7);
      return true;
    }
    i += 2 + size_t(be16(i + 2));
  }
  return false;
}

// Checks what an encoded image claims before any decoder reads it: its pixel count (PNG and
// JPEG headers, read here so that a header a decoder refuses still says why), and that no PNG
// chunk is longer than the data holding it (a decoder may reserve what a length field claims).
void checkClaims(const std::string& encoded, const SourceLocation& where) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(encoded.data());
  const size_t size = encoded.size();
  if (size >= 8 && bytes[0] == 0x89 && bytes[1] == 'P') {
    for (size_t pos = 8; pos + 8 <= size;) {
      const uint64_t length = bigEndian32(bytes + pos);
      if (length > size - pos - 8)
        throw SceneError(where, "a PNG chunk claims " + std::to_string(length) +
                                    " bytes, more than the image holds");
      pos += 12 + size_t(length);  // length, type, data, CRC
    }
  }
  uint64_t w = 0, h = 0;
  if (imageHeaderSize(bytes, size, &w, &h)) checkPixelCount(w, h, where);
}

ImageDesc convertImage(const Image& im, std::shared_ptr<const std::string> encoded, size_t index) {
  ImageDesc d;
  d.name =
      im.uri.empty() || im.uri.rfind("data:", 0) == 0 ? "image " + std::to_string(index) : im.uri;
  d.encoded = std::move(encoded);
  checkClaims(*d.encoded, im.where);
  try {
    const EncodedImageInfo info = oiio::plugin().probeEncodedImage(*d.encoded);
    d.width = info.width, d.height = info.height, d.channels = info.channels, d.bits = info.bits;
  } catch (const FailureError&) {
    throw;  // not the file's fault (the OpenImageIO plugin is missing): exit code 1
  } catch (const std::exception& e) {
    throw SceneError(im.where, e.what());
  }
  checkPixelCount(uint64_t(d.width), uint64_t(d.height), im.where);  // every format
  d.where = im.where;
  return d;
}

// The scene textures a material's texture references read: the file's texture, or a copy of
// it that reads TEXCOORD_1 and/or applies KHR_texture_transform's UV transform (one copy per
// distinct use; the image is shared). Sets above 1 were warned about and read TEXCOORD_0.
class TextureUses {
 public:
  TextureUses(int textureBase, SceneDescription* scene) : base_(textureBase), scene_(scene) {}

  // The scene texture `r` reads (-1: none).
  int operator()(const TextureRef& r) {
    if (r.index < 0) return -1;
    const int base = base_ + r.index;
    const int uvSet = r.texCoord == 1 ? 1 : 0;
    if (!r.transformed && uvSet == 0) return base;
    const auto key =
        std::make_tuple(base, uvSet, r.offset.x, r.offset.y, r.scale.x, r.scale.y, r.rotation);
    if (auto it = copies_.find(key); it != copies_.end()) return it->second;
    TextureDesc t = scene_->textures[size_t(base)];
    t.name += r.transformed ? " (KHR_texture_transform)" : " (TEXCOORD_1)";
    t.mapping.scale = {r.scale.x, r.scale.y, 1};
    t.mapping.offset = {r.offset.x, r.offset.y, 0};
    t.mapping.uvRotation = r.rotation;
    t.mapping.uvSet = uvSet;
    t.where = r.transformed ? r.where.child("extensions").child("KHR_texture_transform") : r.where;
    scene_->textures.push_back(t);
    return copies_[key] = int(scene_->textures.size() - 1);
  }

 private:
  int base_;
  SceneDescription* scene_;
  // (texture, uv set, offset, scale, rotation) -> the copy's index
  std::map<std::tuple<int, int, float, float, float, float, float>, int> copies_;
};

MaterialDesc convertMaterial(const Material& m, TextureUses& texture) {
  MaterialDesc d;
  d.name = m.name;
  // KHR_materials_unlit: the base colour (factor, texture, vertex colours, alpha) alone.
  d.type = m.unlit ? MaterialType::Unlit : MaterialType::Pbr;
  d.baseColor = {m.baseColorFactor.x, m.baseColorFactor.y, m.baseColorFactor.z};
  d.opacity = m.baseColorFactor.w;
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
  const Material::LayerTextures& lt = m.layerTextures;
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
  return d;
}

}  // namespace

void convertMaterials(const Document& doc, const Payload& payload, SceneDescription* scene) {
  const int imageBase = int(scene->images.size());
  const int textureBase = int(scene->textures.size());
  for (size_t i = 0; i < doc.images.size(); ++i)
    scene->images.push_back(convertImage(doc.images[i], payload.images.at(i), i));
  for (const Texture& t : doc.textures) {
    TextureDesc d;
    d.image = imageBase + t.source;
    if (t.sampler >= 0) {
      const Sampler& s = doc.samplers[size_t(t.sampler)];
      d.wrapS = s.wrapS, d.wrapT = s.wrapT;
      d.nearest = s.magFilter == 9728;  // NEAREST
    }
    d.where = t.where;
    scene->textures.push_back(d);
  }
  TextureUses uses(textureBase, scene);
  for (const Material& m : doc.materials) scene->materials.push_back(convertMaterial(m, uses));
}

}  // namespace glint::gltf
