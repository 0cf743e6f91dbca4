// The image texture builtins (docs/language.md section 6, docs/stdlib.md "Image textures"):
// image()/image_data() load a file while the program is checked and become Image constants;
// lookups become the ImageNearest/Bilinear/Trilinear primitives, which give RGBA (Vec4).
#include <filesystem>

#include "lang/checker_builder.h"
#include "lang/image_table.h"

namespace tex::lang {

using ir::Node;
using ir::Prim;

Node* Builder::imageCall(const std::string& name, const Expr* call, Span calleeSpan) {
  bool literal = call->args.size() == 1 && call->args[0].name.empty() && call->args[0].value->kind == Expr::Kind::StringLit;
  if (!literal) {
    for (const Argument& a : call->args)
      if (a.value->kind != Expr::Kind::StringLit) check(a.value);  // report their own errors too
    error("E0410", calleeSpan, "'" + name + "' takes one string literal: the image file's path",
          "e.g. " + name + "(\"textures/wood.png\"), relative to this file's directory");
    return errorNode(call->span);
  }
  const Expr* path = call->args[0].value;
  if (path->intValue) return errorNode(call->span);  // malformed literal, reported by the lexer
  // Relative paths are resolved against the directory of the file that names them, like imports:
  // its canonical directory, as imports take it (through a symlinked file, images had come from
  // the link's directory and imports from the target's).
  std::filesystem::path file(path->name);
  if (file.is_relative() && path->span.file) {
    std::error_code ec;
    std::filesystem::path source = std::filesystem::weakly_canonical(std::filesystem::path(path->span.file->path), ec);
    if (ec) source = path->span.file->path;
    file = source.parent_path() / file;
  }
  ImageLoadResult loaded = ImageTable::global().load(file.string(), name == "image_data");
  if (loaded.handle < 0) {
    error(loaded.code, path->span, loaded.message);
    return errorNode(call->span);
  }
  Node* n = program.node(Node::Kind::Const, types.image(), call->span);
  n->intValue = loaded.handle;
  return n;
}

Node* Builder::imageBuiltin(const std::string& name, std::vector<TypedArg>& args, Span calleeSpan, Span callSpan) {
  bool lookup = name == "sample" || name == "sample_nearest" || name == "sample_alpha" || name == "sample_filtered";
  if (name != "image" && name != "image_data" && name != "image_size" && !lookup) return nullptr;
  auto noOverload = [&](const std::string& expected) {
    std::string got;
    for (auto& a : args) got += (got.empty() ? "" : ", ") + typeName(a.node->type);
    error("E0410", calleeSpan, "no overload of '" + name + "' takes (" + got + ")", "expected " + expected);
    return errorNode(callSpan);
  };
  auto kind = [&](size_t i) { return args[i].node->type->kind; };
  // Reached only through a function value (`let f = image in ...`): the path is then no literal.
  if (name == "image" || name == "image_data") return noOverload("one string literal: the image file's path");
  if (args.empty() || kind(0) != TypeKind::Image) return noOverload("an Image first");
  if (name == "image_size") {
    if (args.size() != 1) return noOverload("(Image)");
    return prim(Prim::ImageSize, types.vec(2), {args[0].node}, callSpan);
  }
  const Type* v2 = types.vec(2);
  std::vector<std::pair<int, Node*>> lets;
  Node *uv = nullptr, *duvdx = nullptr, *duvdy = nullptr;
  size_t next = 1;
  if (name == "sample_filtered" && args.size() >= 2 && kind(1) == TypeKind::Record) {
    // A Hit, or any record with Vec2 fields uv, duvdx and duvdy.
    Node* hit = bindOnce(args[1].node, lets);
    auto field = [&](const char* fieldName) -> Node* {
      const auto& fields = hit->type->fields;
      for (size_t i = 0; i < fields.size(); ++i)
        if (fields[i].first == fieldName && fields[i].second == v2) {
          Node* n = program.node(Node::Kind::GetField, v2, callSpan);
          n->args = {hit};
          n->index = int(i);
          return n;
        }
      return nullptr;
    };
    uv = field("uv"), duvdx = field("duvdx"), duvdy = field("duvdy");
    next = 2;
  } else if (name == "sample_filtered") {
    if (args.size() >= 4 && args[1].node->type == v2 && args[2].node->type == v2 && args[3].node->type == v2)
      uv = args[1].node, duvdx = args[2].node, duvdy = args[3].node;
    next = 4;
  } else if (args.size() >= 2 && args[1].node->type == v2) {
    static const float zeros[2] = {0, 0};
    uv = args[1].node;
    duvdx = constLanes(v2, zeros, callSpan);
    duvdy = constLanes(v2, zeros, callSpan);
    next = 2;
  }
  const char* expected = name == "sample_filtered" ? "(Image, h: Hit) or (Image, uv: Vec2, duvdx: Vec2, duvdy: Vec2), then an optional wrap mode Int"
                                                    : "(Image, uv: Vec2) or (Image, uv: Vec2, wrap: Int)";
  if (!uv || !duvdx || !duvdy || args.size() > next + 1 || (args.size() == next + 1 && kind(next) != TypeKind::Int))
    return noOverload(expected);
  Node* wrap = args.size() == next + 1 ? args[next].node : constInt(int32_t(ImageWrap::Repeat), callSpan);
  Prim p = name == "sample_nearest" ? Prim::ImageNearest : name == "sample_filtered" ? Prim::ImageTrilinear : Prim::ImageBilinear;
  Node* rgba = prim(p, types.vec(4), {args[0].node, uv, duvdx, duvdy, wrap}, callSpan);
  bool alpha = name == "sample_alpha";
  Node* part = prim(Prim::Swizzle, alpha ? types.floating() : types.color(), {rgba}, callSpan);
  part->lanes = alpha ? std::vector<uint8_t>{3} : std::vector<uint8_t>{0, 1, 2};
  return wrapLets(lets, part);
}

}  // namespace tex::lang
