// Scene JSON values with a structure of their own: spectra, transforms, .tex parameters.
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "renderer/scene/scene_json_reader.h"

namespace tex::render {

bool SceneJsonReader::spectrum(const JsonAt& at, SpectrumDesc& out) {
  out = SpectrumDesc{};
  if (at.j->is_number()) {
    if (!std::isfinite(at.j->get<double>())) return error(at, "must be finite"), false;
    out.kind = SpectrumDesc::Kind::Constant;
    out.value = at.j->get<float>();
    return true;
  }
  if (!at.j->is_object())
    return error(at, "expected a spectrum (a number, or an object with rgb, blackbody, named or tabulated), got " +
                         typeName(*at.j)),
           false;
  if (!checkKeys(at, {"rgb", "blackbody", "named", "tabulated", "scale", "as"})) return false;
  int kinds = 0;
  for (const char* k : {"rgb", "blackbody", "named", "tabulated"}) kinds += at.j->contains(k) ? 1 : 0;
  if (kinds != 1) return error(at, "a spectrum needs exactly one of rgb, blackbody, named, tabulated"), false;
  if (child(at, "as") && !child(at, "rgb")) return error(child(at, "as"), "\"as\" applies to rgb spectra only"), false;
  if (!number(at, "scale", out.scale)) return false;
  if (const JsonAt rgb = child(at, "rgb")) {
    std::vector<float> v;
    if (!vector(rgb, 3, 3, v)) return false;
    out.kind = SpectrumDesc::Kind::Rgb;
    out.rgb = Vec3(v[0], v[1], v[2]);
    if (out.rgb.x < 0 || out.rgb.y < 0 || out.rgb.z < 0) return error(rgb, "components must be >= 0"), false;
    if (const JsonAt as = child(at, "as")) {
      std::string use;
      if (!string(at, "as", use)) return false;
      if (use == "reflectance") out.rgbAs = SpectrumDesc::RgbAs::Reflectance;
      else if (use == "unbounded") out.rgbAs = SpectrumDesc::RgbAs::Unbounded;
      else if (use == "illuminant") out.rgbAs = SpectrumDesc::RgbAs::Illuminant;
      else return error(as, "\"as\" must be \"reflectance\", \"unbounded\" or \"illuminant\", got \"" + use + "\""), false;
      if (out.rgbAs == SpectrumDesc::RgbAs::Reflectance && (out.rgb.x > 1 || out.rgb.y > 1 || out.rgb.z > 1))
        return error(rgb, "a reflectance's components must be <= 1"), false;
    }
  } else if (child(at, "blackbody")) {
    out.kind = SpectrumDesc::Kind::Blackbody;
    if (!number(at, "blackbody", out.kelvin, 100.0f, 1e6f)) return false;
  } else if (child(at, "named")) {
    out.kind = SpectrumDesc::Kind::Named;
    if (!string(at, "named", out.name)) return false;
    if (out.name.empty()) return error(child(at, "named"), "the name is empty"), false;
  } else {
    const JsonAt table = child(at, "tabulated");
    if (!isArray(table)) return false;
    if (table.j->size() < 2) return error(table, "needs at least 2 [lambdaNm, value] pairs"), false;
    out.kind = SpectrumDesc::Kind::Tabulated;
    for (size_t i = 0; i < table.j->size(); ++i) {
      std::vector<float> pair;
      if (!vector(element(table, i), 2, 2, pair)) return false;
      if (!out.lambdaNm.empty() && !(pair[0] > out.lambdaNm.back()))
        return error(element(table, i), "wavelengths must increase"), false;
      out.lambdaNm.push_back(pair[0]);
      out.values.push_back(pair[1]);
    }
  }
  return true;
}

bool SceneJsonReader::transform(const JsonAt& at, Mat4& out) {
  out = Mat4(1.0f);
  if (!checkKeys(at, {"matrix", "translate", "rotate", "scale"})) return false;
  if (const JsonAt matrix = child(at, "matrix")) {
    if (keyCount(at) > 1) return error(matrix, "\"matrix\" cannot be combined with translate/rotate/scale"), false;
    std::vector<float> m;
    if (!vector(matrix, 16, 16, m)) return false;
    out = glm::make_mat4(m.data());  // column-major, as glTF
    return true;
  }
  // uniform or per-axis scale, then rotation, then translation (as glTF's TRS)
  Vec3 scale(1.0f);
  if (const JsonAt s = child(at, "scale")) {
    std::vector<float> v;
    if (s.j->is_number()) {
      if (!number(at, "scale", scale.x)) return false;
      scale = Vec3(scale.x);
    } else if (!vector(s, 3, 3, v)) {
      return false;
    } else {
      scale = Vec3(v[0], v[1], v[2]);
    }
    if (scale.x == 0 || scale.y == 0 || scale.z == 0) return error(s, "a scale of 0 collapses the geometry"), false;
  }
  Mat4 rotation(1.0f);
  if (const JsonAt r = child(at, "rotate")) {
    std::vector<float> v;
    if (!vector(r, 4, 4, v)) return false;  // [axis x, y, z, angle in degrees]
    const Vec3 axis(v[0], v[1], v[2]);
    if (!(glm::length(axis) > 0)) return error(r, "the rotation axis is zero"), false;
    rotation = glm::rotate(Mat4(1.0f), glm::radians(v[3]), glm::normalize(axis));
  }
  Vec3 translation(0.0f);
  if (!vec3(at, "translate", translation)) return false;
  out = glm::translate(Mat4(1.0f), translation) * rotation * glm::scale(Mat4(1.0f), scale);
  return true;
}

bool SceneJsonReader::texParam(const JsonAt& at, TexParamValue& out) {
  const nlohmann::json& j = *at.j;
  out = TexParamValue{};
  if (j.is_boolean()) {
    out.kind = TexParamValue::Kind::Bool;
    out.boolValue = j.get<bool>();
  } else if (j.is_number_integer()) {
    // Integers may also feed Float parameters: both forms are filled.
    // Beyond the 32-bit range an integer can only be a Float (3000000000 for a Float parameter
    // had been refused while 3e9 was taken): it is passed as one, and an Int parameter refuses it.
    const int64_t v = j.is_number_unsigned() ? int64_t(std::min<uint64_t>(j.get<uint64_t>(), INT64_MAX)) : j.get<int64_t>();
    if (v < INT32_MIN || v > INT32_MAX) {
      out.kind = TexParamValue::Kind::Float;
      out.floats = {j.is_number_unsigned() ? float(j.get<uint64_t>()) : float(v)};
      return true;
    }
    out.kind = TexParamValue::Kind::Int;
    out.intValue = int32_t(v);
    out.floats = {float(v)};
  } else if (j.is_number()) {
    if (!std::isfinite(j.get<double>())) return error(at, "must be finite"), false;
    out.kind = TexParamValue::Kind::Float;
    out.floats = {j.get<float>()};
  } else if (j.is_array()) {
    out.kind = TexParamValue::Kind::Vec;
    return vector(at, 2, 4, out.floats);
  } else if (j.is_object()) {
    out.kind = TexParamValue::Kind::Spectrum;
    if (j.contains("spectrum")) {
      if (!checkKeys(at, {"spectrum"})) return false;
      return spectrum(child(at, "spectrum"), out.spectrum);
    }
    return spectrum(at, out.spectrum);
  } else {
    return error(at, "expected a boolean, number, array of 2-4 numbers or spectrum, got " + typeName(j)), false;
  }
  return true;
}

}  // namespace tex::render
