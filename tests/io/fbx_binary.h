// binary_fbx_of(ascii): an ASCII FBX file (as assimp's "fbxa" exporter writes it) rewritten as
// a binary FBX ("Kaydara FBX Binary", the FBX SDK's layout): the same nodes and values, typed
// as binary FBX types them, and object names as binary files store them ("Class::name" becomes
// "name\0\x01Class"). The tests' only way to a binary FBX: Debian's assimp 5.2.5 writes binary
// FBX that its own importer refuses (io/assimp/assimp_convert.h), and no other writer is packaged.
//
// Types: arrays by their node's name (int32 for indices and flags, int64 for key times, float32
// for key values, float64 otherwise); a Properties70 P: value by its property type (int, enum,
// bool → int32; KTime, ULongLong → int64; others float64); an object's, a connection's, a
// document's, a pose node's and the root node's ids int64; the few scalars assimp reads as
// floating point (Link_DeformAcuracy, ...) float64; other numbers int32 when integral and within
// range, else float64; quoted strings strings; a bare word (Shading: T) a one-byte flag. Version
// 7400: 32-bit offsets, 13-byte null records. Throws std::runtime_error on text it cannot read.
#pragma once

#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sweepd::io::testing {

namespace fbx_binary_detail {

struct Value {
  enum Kind { kNumber, kString, kWord } kind = kNumber;
  std::string text;
};

struct Node {
  std::string name;
  std::vector<Value> values;
  bool array = false;      // Name: *N { a: ... }
  bool has_block = false;  // written with { }, even when empty
  std::vector<Node> children;
};

class Reader {
 public:
  explicit Reader(std::string_view text) : text_(text) {}

  std::vector<Node> nodes(bool nested) {
    std::vector<Node> out;
    for (skip(); at_ < text_.size(); skip()) {
      if (text_[at_] == '}') {
        if (!nested) fail("a '}' with no block open");
        ++at_;
        return out;
      }
      out.push_back(node());
    }
    if (nested) fail("a block not closed");
    return out;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("ASCII FBX at byte " + std::to_string(at_) + ": " + what);
  }

  void skip() {  // blanks, line ends and ';' comments
    while (at_ < text_.size()) {
      if (std::isspace(static_cast<unsigned char>(text_[at_]))) {
        ++at_;
      } else if (text_[at_] == ';') {
        while (at_ < text_.size() && text_[at_] != '\n') ++at_;
      } else {
        return;
      }
    }
  }

  std::string key() {
    const std::size_t start = at_;
    while (at_ < text_.size() && text_[at_] != ':') ++at_;
    if (at_ == text_.size()) fail("a node name without ':'");
    std::string name(text_.substr(start, at_ - start));
    ++at_;
    return name;
  }

  Value value() {
    skip();
    if (at_ == text_.size()) fail("a value expected at the end");
    if (text_[at_] == '"') {
      const std::size_t end = text_.find('"', at_ + 1);
      if (end == std::string_view::npos) fail("an unterminated string");
      Value v{Value::kString, std::string(text_.substr(at_ + 1, end - at_ - 1))};
      at_ = end + 1;
      return v;
    }
    const std::size_t start = at_;
    while (at_ < text_.size() && text_[at_] != ',' && text_[at_] != '{' && text_[at_] != '}' &&
           !std::isspace(static_cast<unsigned char>(text_[at_])))
      ++at_;
    if (start == at_) fail("a value expected");
    std::string word(text_.substr(start, at_ - start));
    const bool number = std::isdigit(static_cast<unsigned char>(word[0])) || word[0] == '-' ||
                        word[0] == '+' || word[0] == '.';
    return {number ? Value::kNumber : Value::kWord, word};
  }

  // The rest of the line's values, comma-separated (also across line ends after a comma).
  std::vector<Value> values() {
    std::vector<Value> out;
    while (true) {
      while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\t')) ++at_;
      if (at_ == text_.size() || text_[at_] == '\n' || text_[at_] == '\r' || text_[at_] == '{' ||
          text_[at_] == '}')
        return out;
      out.push_back(value());
      while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\t')) ++at_;
      if (at_ < text_.size() && text_[at_] == ',') {
        ++at_;
        skip();  // values go on after a comma, whatever the line
      }
    }
  }

  Node node() {
    Node n;
    n.name = key();
    while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\t')) ++at_;
    if (at_ < text_.size() && text_[at_] == '*') {  // an array: *N { a: v, v, ... }
      n.array = true;
      while (at_ < text_.size() && text_[at_] != '{') ++at_;
      ++at_;
      skip();
      if (key() != "a") fail("an array without 'a:'");
      n.values = values();
      skip();
      if (at_ == text_.size() || text_[at_] != '}') fail("an array not closed");
      ++at_;
      return n;
    }
    n.values = values();
    if (at_ < text_.size() && text_[at_] == '{') {
      ++at_;
      n.has_block = true;
      n.children = nodes(true);
    }
    return n;
  }

  std::string_view text_;
  std::size_t at_ = 0;
};

class Writer {
 public:
  std::vector<std::uint8_t> file(const std::vector<Node>& top) {
    const char magic[] = "Kaydara FBX Binary  ";
    out_.assign(magic, magic + sizeof magic);  // with its NUL
    out_.push_back(0x1a);
    out_.push_back(0x00);
    put32(7400);
    for (const Node& node : top) write(node, "");
    null_record();
    return out_;
  }

 private:
  void put32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void put64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void patch32(std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out_[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
  }
  void null_record() { out_.insert(out_.end(), 13, 0); }

  static bool integral(const std::string& text) {
    return text.find_first_of(".eE") == std::string::npos;
  }

  void number(char type, const std::string& text) {
    out_.push_back(static_cast<std::uint8_t>(type));
    if (type == 'I') {
      put32(static_cast<std::uint32_t>(
          static_cast<std::int32_t>(std::strtol(text.c_str(), nullptr, 10))));
    } else if (type == 'L') {
      put64(static_cast<std::uint64_t>(std::strtoll(text.c_str(), nullptr, 10)));
    } else {
      const double d = std::strtod(text.c_str(), nullptr);
      std::uint64_t bits;
      std::memcpy(&bits, &d, 8);
      put64(bits);
    }
  }

  void string(const std::string& s) {
    out_.push_back('S');
    put32(static_cast<std::uint32_t>(s.size()));
    out_.insert(out_.end(), s.begin(), s.end());
  }

  void array(const Node& node) {
    static const std::set<std::string> int32s = {
        "PolygonVertexIndex", "Edges",           "UVIndex",      "Materials",      "Indexes",
        "KeyAttrFlags",       "KeyAttrRefCount", "NormalsIndex", "BinormalsIndex", "TangentsIndex",
        "ColorIndex",         "Smoothing"};
    const char type = int32s.count(node.name)                                           ? 'i'
                      : node.name == "KeyTime"                                          ? 'l'
                      : node.name == "KeyValueFloat" || node.name == "KeyAttrDataFloat" ? 'f'
                                                                                        : 'd';
    const std::size_t stride = type == 'i' || type == 'f' ? 4 : 8;
    out_.push_back(static_cast<std::uint8_t>(type));
    put32(static_cast<std::uint32_t>(node.values.size()));
    put32(0);  // not compressed
    put32(static_cast<std::uint32_t>(node.values.size() * stride));
    for (const Value& v : node.values) {
      const char* c = v.text.c_str();
      if (type == 'i') {
        put32(static_cast<std::uint32_t>(static_cast<std::int32_t>(std::strtol(c, nullptr, 10))));
      } else if (type == 'l') {
        put64(static_cast<std::uint64_t>(std::strtoll(c, nullptr, 10)));
      } else if (type == 'f') {
        const float f = std::strtof(c, nullptr);
        std::uint32_t bits;
        std::memcpy(&bits, &f, 4);
        put32(bits);
      } else {
        const double d = std::strtod(c, nullptr);
        std::uint64_t bits;
        std::memcpy(&bits, &d, 8);
        put64(bits);
      }
    }
  }

  // Values outside Properties70 that assimp reads as floating point, written as integers in
  // ASCII when whole (Link_DeformAcuracy: 50).
  static const std::set<std::string>& float_scalars() {
    static const std::set<std::string> names = {"Link_DeformAcuracy", "DeformPercent",
                                                "ModelUVTranslation", "ModelUVScaling", "Alphas"};
    return names;
  }

  // The type a P: value takes from the property's type name (its second value).
  static char property_type(const std::string& type) {
    static const std::set<std::string> int32s = {
        "int", "Int", "enum", "Enum", "Integer", "bool", "Bool", "Visibility Inheritance"};
    if (int32s.count(type)) return 'I';
    if (type == "KTime" || type == "ULongLong") return 'L';
    return 'D';
  }

  void values(const Node& node, const std::string& parent) {
    for (std::size_t i = 0; i < node.values.size(); ++i) {
      const Value& v = node.values[i];
      if (v.kind == Value::kString) {
        std::string s = v.text;
        const std::size_t colons = s.find("::");
        if (parent == "Objects" && i == 1 && colons != std::string::npos) {
          s = s.substr(colons + 2) + std::string("\0\x01", 2) + s.substr(0, colons);
        }
        string(s);
      } else if (v.kind == Value::kWord) {
        out_.push_back('C');
        out_.push_back(static_cast<std::uint8_t>(v.text[0]));
      } else if (node.name == "P" && i >= 4) {
        number(property_type(node.values[1].text), v.text);
      } else if (((parent == "Objects" || parent == "Documents") && i == 0) ||
                 (node.name == "C" && i >= 1) || (node.name == "Node" && parent == "PoseNode") ||
                 node.name == "RootNode") {
        number('L', v.text);
      } else if (float_scalars().count(node.name)) {
        number('D', v.text);
      } else if (integral(v.text)) {
        const long long n = std::strtoll(v.text.c_str(), nullptr, 10);
        const bool fits = n >= std::numeric_limits<std::int32_t>::min() &&
                          n <= std::numeric_limits<std::int32_t>::max();
        number(fits ? 'I' : 'L', v.text);
      } else {
        number('D', v.text);
      }
    }
  }

  void write(const Node& node, const std::string& parent) {
    const std::size_t start = out_.size();
    put32(0);  // end offset, patched below
    put32(node.array ? 1 : static_cast<std::uint32_t>(node.values.size()));
    put32(0);  // property bytes, patched below
    out_.push_back(static_cast<std::uint8_t>(node.name.size()));
    out_.insert(out_.end(), node.name.begin(), node.name.end());
    const std::size_t properties = out_.size();
    if (node.array) {
      array(node);
    } else {
      values(node, parent);
    }
    patch32(start + 8, static_cast<std::uint32_t>(out_.size() - properties));
    if (node.has_block) {
      for (const Node& child : node.children) write(child, node.name);
      null_record();
    }
    patch32(start, static_cast<std::uint32_t>(out_.size()));
  }

  std::vector<std::uint8_t> out_;
};

}  // namespace fbx_binary_detail

inline std::vector<std::uint8_t> binary_fbx_of(std::string_view ascii) {
  fbx_binary_detail::Reader reader(ascii);
  return fbx_binary_detail::Writer().file(reader.nodes(false));
}

}  // namespace sweepd::io::testing
