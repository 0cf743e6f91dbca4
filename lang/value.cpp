#include "lang/value.h"

#include <charconv>
#include <cmath>
#include <filesystem>

#include "lang/core_ir.h"
#include "lang/image_table.h"

namespace tex::lang {

int lanesOf(const Type* t, const WavelengthGroup& group) {
  return t->kind == TypeKind::Spectrum ? group.count : t->fixedLanes();
}

std::string formatFloat(float x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[64];
  auto result = std::to_chars(buf, buf + sizeof buf, x);
  std::string s(buf, result.ptr);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

static std::string lanes(const char* prefix, const Value& v, int n) {
  std::string s = std::string(prefix) + "(";
  for (int i = 0; i < n; ++i) s += (i ? ", " : "") + formatFloat(v.f[i]);
  return s + ")";
}

// `budget`: nodes still to print. A material can share nodes (add_material(m, m) nested 30 deep
// is 31 nodes that print as 2^30 calls, which hung the REPL), so printing stops after
// kMaterialPrintBudget nodes and writes "..." for the rest.
constexpr int kMaterialPrintBudget = 256;

static std::string formatMaterial(const MaterialNode* m, const WavelengthGroup& group, int& budget) {
  const ir::MaterialShape* shape = m ? ir::materialShapeOfKind(uint32_t(m->kind)) : nullptr;
  if (!shape) return "<material>";
  if (--budget < 0) return "...";
  // A node prints as the call that builds it: children, parameters, scalars, the Mix weight;
  // a roughness of 0 (the default) is left out, another is named; a dielectric's or thin wall's
  // transmission tint comes last, named, and is left out when it is the default 1; ", varying" marks a
  // wavelength-dependent node.
  std::vector<std::string> parts;
  const bool tinted = m->kind == MaterialNode::Kind::ThinDielectric || m->kind == MaterialNode::Kind::Dielectric;
  if (shape->children > 0) parts.push_back(formatMaterial(m->a.get(), group, budget));
  if (shape->children > 1) parts.push_back(formatMaterial(m->b.get(), group, budget));
  if (shape->params > 0) parts.push_back(formatValue(m->param, m->paramType, group));
  if (shape->params > 1 && !tinted) parts.push_back(formatValue(m->param2, m->param2Type, group));
  bool roughness = m->kind == MaterialNode::Kind::Dielectric || m->kind == MaterialNode::Kind::Conductor ||
                   m->kind == MaterialNode::Kind::ThinDielectric;
  const bool anisotropic = roughness && (m->flags & kMaterialAnisotropic);
  if (anisotropic)  // a Vec2 roughness is printed even when zero: it makes the node anisotropic
    parts.push_back("roughness: vec2(" + formatFloat(m->scalars[0]) + ", " + formatFloat(m->scalars[1]) + ")");
  for (int i = 0; i < shape->scalars && !anisotropic; ++i) {
    if (!roughness) parts.push_back(formatFloat(m->scalars[i]));
    else if (m->scalars[i] != 0.0f) parts.push_back("roughness: " + formatFloat(m->scalars[i]));
  }
  if (shape->weight) parts.push_back(formatFloat(m->weight));
  if (tinted && shape->params > 1) {
    bool untinted = true;
    for (int i = 0; i < lanesOf(m->param2Type, group); ++i) untinted = untinted && m->param2.f[i] == 1.0f;
    if (!untinted) parts.push_back("transmission_tint: " + formatValue(m->param2, m->param2Type, group));
  }
  if (anisotropic && m->scalars[2] != 0.0f) parts.push_back("rotation: " + formatFloat(m->scalars[2]));
  if (m->flags & kMaterialVariesWithWavelength) parts.push_back("varying");
  std::string s = std::string(ir::materialBuiltinName(uint32_t(m->kind))) + "(";
  for (size_t i = 0; i < parts.size(); ++i) s += (i ? ", " : "") + parts[i];
  return s + ")";
}

std::string formatValue(const Value& v, const Type* t, const WavelengthGroup& group) {
  switch (t->kind) {
    case TypeKind::Bool: return v.i ? "true" : "false";
    case TypeKind::Int: return std::to_string(v.i);
    case TypeKind::Float: return formatFloat(v.f[0]);
    case TypeKind::Vec2: return lanes("vec2", v, 2);
    case TypeKind::Vec3: return lanes("vec3", v, 3);
    case TypeKind::Vec4: return lanes("vec4", v, 4);
    case TypeKind::Color: return lanes("rgb", v, 3);
    case TypeKind::Spectrum: return lanes("spectrum", v, group.count);
    case TypeKind::Material: {
      int budget = kMaterialPrintBudget;
      return formatMaterial(v.material.get(), group, budget);
    }
    case TypeKind::Image: {
      // The file name and size: the handle is process-specific and the full path machine-specific.
      const LoadedImage* image = ImageTable::global().get(v.i);
      if (!image) return "<image>";
      std::string name = std::filesystem::path(image->path).filename().string();
      return "<image " + name + " " + std::to_string(image->levels[0].width) + "x" + std::to_string(image->levels[0].height) + ">";
    }
    case TypeKind::Record: {
      std::string s = "{";
      for (size_t i = 0; i < t->fields.size(); ++i) {
        s += (i ? ", " : "") + t->fields[i].first + ": ";
        s += v.fields && i < v.fields->size() ? formatValue((*v.fields)[i], t->fields[i].second, group) : "?";
      }
      return s + "}";
    }
    case TypeKind::FuncRef:
    case TypeKind::BuiltinRef:
    case TypeKind::Lambda:
    case TypeKind::Function: return "<function>";
    case TypeKind::Error: return "<error>";
  }
  return "?";
}

}  // namespace tex::lang
