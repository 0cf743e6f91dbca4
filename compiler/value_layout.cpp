#include "compiler/value_layout.h"

#include <cstring>

#include "lang/core_ir.h"

namespace tex::compiler {

static_assert(lang::kMaterialAnisotropic == kClosureAnisotropic &&
                  lang::kMaterialVariesWithWavelength == kClosureVariesWithWavelength,
              "the interpreter's material flags are the ABI's");

// The interpreter's material kinds are the ABI's closure kinds.
static_assert(uint32_t(lang::MaterialNode::Kind::Diffuse) == uint32_t(ClosureKind::Diffuse) &&
                  uint32_t(lang::MaterialNode::Kind::Emission) == uint32_t(ClosureKind::Emission) &&
                  uint32_t(lang::MaterialNode::Kind::Mix) == uint32_t(ClosureKind::Mix) &&
                  uint32_t(lang::MaterialNode::Kind::Dielectric) == uint32_t(ClosureKind::Dielectric) &&
                  uint32_t(lang::MaterialNode::Kind::Conductor) == uint32_t(ClosureKind::Conductor) &&
                  uint32_t(lang::MaterialNode::Kind::ThinDielectric) == uint32_t(ClosureKind::ThinDielectric) &&
                  uint32_t(lang::MaterialNode::Kind::Glossy) == uint32_t(ClosureKind::Glossy) &&
                  uint32_t(lang::MaterialNode::Kind::GlossyDielectric) == uint32_t(ClosureKind::GlossyDielectric) &&
                  uint32_t(lang::MaterialNode::Kind::Layer) == uint32_t(ClosureKind::Layer) &&
                  uint32_t(lang::MaterialNode::Kind::Scale) == uint32_t(ClosureKind::Scale) &&
                  uint32_t(lang::MaterialNode::Kind::Add) == uint32_t(ClosureKind::Add) &&
                  uint32_t(lang::MaterialNode::Kind::Sheen) == uint32_t(ClosureKind::Sheen),
              "MaterialNode::Kind follows ClosureKind");

using lang::Type;
using lang::TypeKind;
using lang::Value;

namespace {

uint32_t floatBits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
float bitsFloat(uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}
int lanes(const Type* t, int wavelengths) { return t->kind == TypeKind::Spectrum ? wavelengths : t->fixedLanes(); }

// The material tree rooted at node `index`, sharing what the arena shares: children are nodes
// appended earlier (docs/abi.md), so a child index not below its parent's is malformed (null),
// and `built` memoises each node, so add_material(m, m) nested 30 deep is 31 nodes, not 2^30.
std::shared_ptr<const lang::MaterialNode> materialFromArena(const ClosureArena* arena, int32_t index, int wavelengths,
                                                            int32_t parent,
                                                            std::vector<std::shared_ptr<const lang::MaterialNode>>& built) {
  if (!arena || index < 0 || index >= arena->count || index >= parent) return nullptr;
  if (built[size_t(index)]) return built[size_t(index)];
  const ClosureNode& node = arena->nodes[index];
  auto m = std::make_shared<lang::MaterialNode>();
  auto& types = lang::TypeTable::global();
  auto param = [&](ClosureParam kind, const float* from, const lang::Type*& type, lang::Value& value) {
    type = kind == ClosureParam::Color ? types.color() : types.spectrum();
    int n = kind == ClosureParam::Color ? 3 : wavelengths;
    for (int i = 0; i < n; ++i) value.f[i] = from[i];
  };
  const lang::ir::MaterialShape* shape = lang::ir::materialShapeOfKind(uint32_t(node.kind));
  if (!shape) return nullptr;  // a kind this compiler never produces
  m->kind = lang::MaterialNode::Kind(shape->kind);
  m->flags = node.flags;
  if (shape->children > 0) m->a = materialFromArena(arena, node.a, wavelengths, index, built);
  if (shape->children > 1) m->b = materialFromArena(arena, node.b, wavelengths, index, built);
  if (shape->params > 0) param(node.paramKind, node.params, m->paramType, m->param);
  if (shape->params > 1) param(node.param2Kind, node.params2, m->param2Type, m->param2);
  const int scalars = (node.flags & kClosureAnisotropic) && shape->anisotropicScalars ? shape->anisotropicScalars : shape->scalars;
  for (int i = 0; i < scalars; ++i) m->scalars[i] = node.scalars[i];
  if (shape->weight) m->weight = node.weight;
  built[size_t(index)] = m;
  return m;
}

}  // namespace

void flatten(const Value& value, const Type* type, int wavelengths, std::vector<uint32_t>& words) {
  switch (type->kind) {
    case TypeKind::Bool:
    case TypeKind::Int:
    case TypeKind::Image: words.push_back(uint32_t(value.i)); return;
    case TypeKind::Material: words.push_back(uint32_t(-1)); return;  // materials are outputs only
    case TypeKind::Record:
    case TypeKind::Lambda:
      for (size_t i = 0; i < type->fields.size(); ++i)
        flatten(value.fields ? (*value.fields)[i] : Value{}, type->fields[i].second, wavelengths, words);
      return;
    default:
      for (int i = 0; i < lanes(type, wavelengths); ++i) words.push_back(floatBits(value.f[i]));
  }
}

static Value unflattenAt(const uint32_t* words, size_t& at, const Type* type, int wavelengths, const ClosureArena* arena) {
  Value v;
  switch (type->kind) {
    case TypeKind::Bool: v.i = words[at++] != 0; return v;
    case TypeKind::Int:
    case TypeKind::Image: v.i = int32_t(words[at++]); return v;
    case TypeKind::Material: {
      std::vector<std::shared_ptr<const lang::MaterialNode>> built(arena ? size_t(std::max(arena->count, 0)) : 0);
      v.material = materialFromArena(arena, int32_t(words[at++]), wavelengths, arena ? arena->count : 0, built);
      return v;
    }
    case TypeKind::Record:
    case TypeKind::Lambda: {
      auto fields = std::make_shared<std::vector<Value>>();
      for (auto& f : type->fields) fields->push_back(unflattenAt(words, at, f.second, wavelengths, arena));
      v.fields = std::move(fields);
      return v;
    }
    default:
      for (int i = 0; i < lanes(type, wavelengths); ++i) v.f[i] = bitsFloat(words[at++]);
      return v;
  }
}

Value unflatten(const uint32_t* words, const Type* type, int wavelengths, const ClosureArena* arena) {
  size_t at = 0;
  return unflattenAt(words, at, type, wavelengths, arena);
}

}  // namespace tex::compiler
