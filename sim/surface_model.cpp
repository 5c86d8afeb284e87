#include "sim/surface_model.h"

#include <algorithm>

#include "common/srgb.h"

namespace mopad::sim {

double SrgbTables::EncodeExact(double l) { return LinearToSrgb(l); }

double SrgbTables::DecodeExact(double s) { return SrgbToLinear(s); }

SrgbTables::SrgbTables() : encode_(kEncodeSize) {
  for (int i = 0; i < 256; ++i) decode_[i] = static_cast<float>(DecodeExact(i / 255.0));
  for (int i = 0; i < kEncodeSize; ++i)
    encode_[i] =
        static_cast<float>(255.0 * EncodeExact(static_cast<double>(i) / (kEncodeSize - 1)));
}

const SrgbTables& SrgbTables::Get() {
  static const SrgbTables tables;
  return tables;
}

namespace {

// Mean linear colour of a texture (for the laser reflectance of textured materials).
Eigen::Vector3f MeanLinear(const scenes::Texture& t) {
  const auto& srgb = SrgbTables::Get();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const std::size_t n = static_cast<std::size_t>(t.width) * t.height;
  if (n == 0 || t.rgba.size() < 4 * n) return Eigen::Vector3f::Ones();
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) sum[c] += srgb.Decode(t.rgba[4 * i + c]);
  return (sum / static_cast<double>(n)).cast<float>();
}

}  // namespace

SurfaceTable::SurfaceTable(const EmbreeWorld& world) {
  const scenes::Scene& scene = world.scene();
  const scenes::Material default_material;
  // The scene's materials, the default, then the movers' (untextured: textures are the scene's).
  std::vector<const scenes::Material*> materials;
  for (const auto& m : scene.materials) materials.push_back(&m);
  materials.push_back(&default_material);
  std::vector<std::size_t> material_of_part(static_cast<std::size_t>(world.PartCount()));
  for (std::int32_t p = 0; p < world.PartCount(); ++p) {
    const scenes::Material* m = world.MaterialOf(p);
    std::size_t index = scene.materials.size();
    if (m && p < static_cast<std::int32_t>(scene.parts.size())) {
      index = static_cast<std::size_t>(scene.parts[static_cast<std::size_t>(p)].material);
    } else if (m) {
      index = materials.size();
      materials.push_back(m);
    }
    material_of_part[static_cast<std::size_t>(p)] = index;
  }
  std::vector<SurfaceProps> by_material(materials.size());
  for (std::size_t m = 0; m < materials.size(); ++m) {
    const scenes::Material& mat = *materials[m];
    const bool own = m < scene.materials.size();
    SurfaceProps s;
    s.base_linear = mat.base_color.head<3>().cwiseMax(0.f).cwiseMin(1.f);
    Eigen::Vector3f albedo = s.base_linear;
    if (own && mat.base_color_texture >= 0 &&
        mat.base_color_texture < static_cast<int>(scene.textures.size())) {
      const scenes::Texture& t = scene.textures[static_cast<std::size_t>(mat.base_color_texture)];
      if (t.width > 0 && t.height > 0 &&
          t.rgba.size() >= static_cast<std::size_t>(t.width) * t.height * 4) {
        s.texture = &t;
        albedo = albedo.cwiseProduct(MeanLinear(t));
      }
    }
    // Laser reflectance: the material's own NIR value, else the visible luminance (Rec. 709).
    const float luminance = 0.2126f * albedo.x() + 0.7152f * albedo.y() + 0.0722f * albedo.z();
    s.reflectance =
        std::clamp(mat.nir_reflectance >= 0.f ? mat.nir_reflectance : luminance, 0.f, 1.f);
    s.transmission = std::clamp(mat.transmission, 0.f, 1.f);
    // A transmitting surface (glass) scatters back only what it does not let through.
    s.reflectance *= 1.f - s.transmission;
    s.metallic = std::clamp(mat.metallic, 0.f, 1.f);
    s.specular_f0 = 0.04f * (1.f - s.metallic) + s.reflectance * s.metallic;
    s.alpha = std::max(mat.roughness * mat.roughness, 0.01f);  // Beckmann alpha = roughness^2
    s.lobe_inv_a2 = 1.0f / (s.alpha * s.alpha);
    s.lobe_scale = s.specular_f0 / (4.0f * s.alpha * s.alpha);
    by_material[m] = s;
  }
  const std::size_t stride = kRhoTableSize + 1;
  rho_tables_.resize(by_material.size() * stride);
  for (std::size_t m = 0; m < by_material.size(); ++m) {
    float* t = rho_tables_.data() + m * stride;
    for (int i = 0; i <= kRhoTableSize; ++i) {
      const double sv = static_cast<double>(i) / kRhoTableSize;
      const float c = static_cast<float>(std::max(1.0 - sv * sv, 1e-4));
      t[i] = EffectiveReflectance(by_material[m], c);
    }
    by_material[m].rho_table = t;
    by_material[m].rho_offset = static_cast<std::int32_t>(m * stride);
  }
  parts_.resize(material_of_part.size());
  for (std::size_t p = 0; p < parts_.size(); ++p) {
    const auto part = static_cast<std::int32_t>(p);
    parts_[p] = by_material[material_of_part[p]];
    parts_[p].element = world.ElementIndex(part);
    parts_[p].element_class = static_cast<std::uint8_t>(world.Part(part).element_class);
  }
}

Eigen::Vector3f SurfaceTable::Textured(const EmbreeWorld& world, const RayHit& hit,
                                       const SurfaceProps& s) const {
  const scenes::MeshPart& mp = world.Part(hit.part);
  if (mp.uvs.empty()) return s.base_linear;
  const Eigen::Vector3i& tri = mp.triangles[hit.triangle];
  const Eigen::Vector2f uv =
      (1.f - hit.u - hit.v) * mp.uvs[tri[0]] + hit.u * mp.uvs[tri[1]] + hit.v * mp.uvs[tri[2]];
  const scenes::Texture& t = *s.texture;
  // Bilinear filtering on texel centres; glTF UV (0, 0) is the top-left corner, row 0 on top.
  const float fx = uv.x() * t.width - 0.5f;
  const float fy = uv.y() * t.height - 0.5f;
  // floor without a libm call (no SSE4.1 in the baseline x86-64 target)
  auto ifloor = [](float v) {
    const long i = static_cast<long>(v);
    return v < static_cast<float>(i) ? i - 1 : i;
  };
  const long x0i = ifloor(fx), y0i = ifloor(fy);
  const float ax = fx - static_cast<float>(x0i), ay = fy - static_cast<float>(y0i);
  auto wrap = [&](long i, int n) -> long {
    if (t.repeat) {
      i %= n;
      return i < 0 ? i + n : i;
    }
    return std::clamp<long>(i, 0, n - 1);
  };
  const long x0 = wrap(x0i, t.width), x1 = wrap(x0i + 1, t.width);
  const long y0 = wrap(y0i, t.height), y1 = wrap(y0i + 1, t.height);
  const auto& srgb = SrgbTables::Get();
  auto texel = [&](long x, long y) {
    const std::uint8_t* p = &t.rgba[4 * (static_cast<std::size_t>(y) * t.width + x)];
    return Eigen::Vector3f(srgb.Decode(p[0]), srgb.Decode(p[1]), srgb.Decode(p[2]));
  };
  const Eigen::Vector3f c = (1 - ay) * ((1 - ax) * texel(x0, y0) + ax * texel(x1, y0)) +
                            ay * ((1 - ax) * texel(x0, y1) + ax * texel(x1, y1));
  return s.base_linear.cwiseProduct(c);
}

}  // namespace mopad::sim
