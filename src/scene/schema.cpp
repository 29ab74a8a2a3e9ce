#include "traverse/scene/schema.hpp"

#include <Teuchos_ParameterList.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>

namespace traverse::scene {

using Teuchos::ParameterList;

// ---------------------------------------------------------------------------------------
// Param builders
// ---------------------------------------------------------------------------------------
namespace {
Param make(const std::string& name, ValueKind kind, const std::string& doc, const std::string& units) {
  Param p;
  p.name = name;
  p.kind = kind;
  p.doc = doc;
  p.units = units;
  return p;
}

std::string fmt(double v) { return format_number(v); }
}  // namespace

std::string format_number(double v) {
  std::ostringstream os;
  os << std::setprecision(12) << v;
  return os.str();
}

Param real(const std::string& n, const std::string& d, const std::string& u) { return make(n, ValueKind::Real, d, u); }
Param integer(const std::string& n, const std::string& d) { return make(n, ValueKind::Integer, d, ""); }
Param boolean(const std::string& n, const std::string& d) { return make(n, ValueKind::Bool, d, ""); }
Param text(const std::string& n, const std::string& d) { return make(n, ValueKind::String, d, ""); }
Param choice(const std::string& n, const std::string& d, std::vector<std::string> words) {
  Param p = make(n, ValueKind::Choice, d, "");
  p.choices = std::move(words);
  return p;
}
Param vector3(const std::string& n, const std::string& d, const std::string& u) { return make(n, ValueKind::Vector3, d, u); }
Param real_list(const std::string& n, const std::string& d, const std::string& u) { return make(n, ValueKind::RealList, d, u); }
Param word_list(const std::string& n, const std::string& d, std::vector<std::string> words) {
  Param p = make(n, ValueKind::StringList, d, "");
  p.choices = std::move(words);
  return p;
}
Param section(const std::string& n, const std::string& d) { return make(n, ValueKind::Section, d, ""); }
Param typed(const std::string& n, const std::string& d, std::shared_ptr<const TypeRegistry> r) {
  Param p = make(n, ValueKind::Typed, d, "");
  p.registry = std::move(r);
  return p;
}
Param collection(const std::string& n, const std::string& d, std::shared_ptr<const TypeRegistry> r) {
  Param p = make(n, ValueKind::Collection, d, "");
  p.registry = std::move(r);
  return p;
}
Param pass_through(const std::string& n, const std::string& d) { return make(n, ValueKind::PassThrough, d, ""); }

Param& Param::required() { is_required = true; return *this; }
Param& Param::def(const std::string& yaml_text) { default_text = yaml_text; return *this; }
Param& Param::def(double value) { default_text = fmt(value); return *this; }
Param& Param::allow_auto() { accepts_auto = true; return *this; }
Param& Param::only_if_given() { omit_when_absent = true; return *this; }
Param& Param::when(const std::string& sibling, const std::string& v) { condition = {sibling, v}; return *this; }
Param& Param::positive() { lo = 0.0; lo_open = true; return *this; }
Param& Param::non_negative() { lo = 0.0; lo_open = false; return *this; }
Param& Param::at_least(double v) { lo = v; lo_open = false; return *this; }
Param& Param::above(double v) { lo = v; lo_open = true; return *this; }
Param& Param::at_most(double v) { hi = v; hi_open = false; return *this; }
Param& Param::below(double v) { hi = v; hi_open = true; return *this; }
Param& Param::add(const Param& child) { children.push_back(child); return *this; }
Param& Param::check(Check c) { checks.push_back(std::move(c)); return *this; }

std::string Param::range_text() const {
  if (kind == ValueKind::Choice || (kind == ValueKind::StringList && !choices.empty())) {
    std::string s = "one of {";
    for (size_t i = 0; i < choices.size(); ++i) s += (i ? ", " : "") + choices[i];
    return s + "}";
  }
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi) return std::string("in ") + (lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + (hi_open ? ")" : "]");
  if (has_lo) return std::string(lo_open ? "> " : ">= ") + fmt(lo);
  if (has_hi) return std::string(hi_open ? "< " : "<= ") + fmt(hi);
  return "";
}

std::string Param::expected_text() const {
  std::string base;
  switch (kind) {
    case ValueKind::Real: base = "a finite real number"; break;
    case ValueKind::Integer: base = "a whole number"; break;
    case ValueKind::Bool: base = "true or false"; break;
    case ValueKind::String: base = "a text value"; break;
    case ValueKind::Choice: return range_text();
    case ValueKind::Vector3: base = "a list of 3 finite real numbers [x, y, z]"; break;
    case ValueKind::RealList: base = "a list of finite real numbers"; break;
    case ValueKind::StringList: base = "a list of words"; break;
    case ValueKind::Section: base = "a map of keys"; break;
    case ValueKind::Typed: base = "a map with a 'type' key"; break;
    case ValueKind::Collection: base = "a map of named entries"; break;
    case ValueKind::PassThrough: base = "a map of solver parameters"; break;
    default: throw std::logic_error("Param::expected_text: unknown value kind");
  }
  const std::string r = range_text();
  std::string s = r.empty() ? base : base + " " + r;
  if (!units.empty()) s += " [" + units + "]";
  if (accepts_auto) s += ", or 'auto'";
  return s;
}

// ---------------------------------------------------------------------------------------
// Registry
// ---------------------------------------------------------------------------------------
TypeRegistry& TypeRegistry::add(TypeInfo info) {
  const std::string n = info.name;
  types_[n] = std::move(info);
  return *this;
}
const TypeInfo* TypeRegistry::find(const std::string& name) const {
  auto it = types_.find(name);
  return it == types_.end() ? nullptr : &it->second;
}
std::vector<std::string> TypeRegistry::names() const {
  std::vector<std::string> v;
  for (const auto& [k, _] : types_) v.push_back(k);
  return v;
}

// ---------------------------------------------------------------------------------------
// Validation
// ---------------------------------------------------------------------------------------
namespace {

using Marks = std::map<std::string, std::pair<int, int>>;

std::string join_path(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string location(const std::string& file, const Marks& marks, const std::string& path) {
  // The key's own mark, else the nearest enclosing key's. Keys set on the command line are
  // marked with line -1 and named as such.
  std::string p = path;
  while (true) {
    auto it = marks.find(p);
    if (it != marks.end() && it->second.first < 0) return file + " (set by --set " + p + ")";
    if (it != marks.end()) return file + ":" + std::to_string(it->second.first) + ":" + std::to_string(it->second.second);
    const auto dot = p.rfind('.');
    if (dot == std::string::npos) break;
    p = p.substr(0, dot);
  }
  return file;
}

std::string shown(const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) return "nothing";
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) {
    YAML::Emitter e;
    e << YAML::Flow << n;
    return "the list " + std::string(e.c_str());
  }
  return "a map";
}

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string suggestion(const std::string& word, const std::vector<std::string>& known) {
  std::string best;
  size_t best_d = std::max<size_t>(2, word.size() / 3) + 1;
  for (const auto& k : known) {
    const size_t d = edit_distance(word, k);
    if (d < best_d) { best_d = d; best = k; }
  }
  return best.empty() ? "" : " (did you mean '" + best + "'?)";
}

std::string list_words(const std::vector<std::string>& w) {
  std::string s;
  for (size_t i = 0; i < w.size(); ++i) s += (i ? ", " : "") + w[i];
  return s;
}

class Validator {
 public:
  Validator(std::string file, Marks& marks) : file_(std::move(file)), marks_(marks) {}

  [[noreturn]] void fail(const std::string& path, const std::string& expected, const std::string& found) const {
    throw SceneError(location(file_, marks_, path) + ": " + (path.empty() ? "(top level)" : path) +
                     ": expected " + expected + ", found " + found);
  }

  void record(const std::string& path, const YAML::Node& n) {
    if (overridden(path)) return;
    const YAML::Mark m = n.Mark();
    if (!m.is_null()) marks_[path] = {m.line + 1, m.column + 1};
  }

  // Validates the keys of a map node against `params` into `out`.
  void map_keys(const YAML::Node& node, const std::vector<Param>& params, const std::string& path,
                ParameterList& out, const std::vector<std::string>& extra_allowed = {}) {
    if (node.IsDefined() && !node.IsNull() && !node.IsMap()) fail(path, "a map of keys", shown(node));
    std::set<std::string> seen;
    std::vector<std::string> known = extra_allowed;
    for (const auto& p : params) known.push_back(p.name);
    if (node.IsMap()) {
      for (const auto& kv : node) {
        const std::string key = kv.first.Scalar();
        const std::string kpath = join_path(path, key);
        record(kpath, kv.first);
        if (!seen.insert(key).second) fail(kpath, "each key once", "a second '" + key + "'");
        if (std::find(known.begin(), known.end(), key) == known.end())
          fail(kpath, "one of the keys {" + list_words(known) + "}", "unknown key '" + key + "'" + suggestion(key, known));
      }
    }
    for (const auto& p : params) {
      const YAML::Node child = node.IsMap() ? node[p.name] : YAML::Node();
      if (!p.condition.first.empty()) {
        const auto& [key, wanted] = p.condition;
        const bool applies = out.isType<std::string>(key) && out.get<std::string>(key) == wanted;
        if (!applies) {
          if (child.IsDefined() && !child.IsNull())
            fail(join_path(path, p.name), "no '" + p.name + "' here: it applies only with " + key + ": " + wanted,
                 "'" + p.name + "' with " + key + ": " + (out.isType<std::string>(key) ? out.get<std::string>(key) : "?"));
          continue;
        }
      }
      value(child, p, join_path(path, p.name), out);
    }
  }

  double real_value(const YAML::Node& n, const Param& p, const std::string& path) {
    if (!n.IsScalar()) fail(path, p.expected_text(), shown(n));
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(path, p.expected_text(), shown(n));
    }
    if (!std::isfinite(v)) fail(path, p.expected_text(), shown(n) + " (not finite)");
    return v;
  }

  void check_range(double v, const Param& p, const std::string& path, const std::string& found) {
    const bool low = p.lo_open ? !(v > p.lo) : !(v >= p.lo);
    const bool high = p.hi_open ? !(v < p.hi) : !(v <= p.hi);
    if (low || high) fail(path, p.expected_text(), found);
  }

  void value(const YAML::Node& n, const Param& p, const std::string& path, ParameterList& out) {
    const bool present = n.IsDefined() && !n.IsNull();
    const bool container = p.kind == ValueKind::Section || p.kind == ValueKind::Collection ||
                           p.kind == ValueKind::PassThrough;
    if (!present) {
      if (p.default_text) {
        value(YAML::Load(*p.default_text), p, path, out);
        return;
      }
      if (p.is_required) fail(path, p.expected_text() + " (required key '" + p.name + "' is missing)", "nothing");
      if (container && !p.omit_when_absent) value(YAML::Node(YAML::NodeType::Map), p, path, out);
      return;
    }
    if (p.accepts_auto && n.IsScalar() && n.Scalar() == "auto") {
      out.set(p.name, std::string("auto"));
      return;
    }
    switch (p.kind) {
      case ValueKind::Real: {
        const double v = real_value(n, p, path);
        check_range(v, p, path, shown(n));
        out.set(p.name, v);
        break;
      }
      case ValueKind::Integer: out.set(p.name, integer_value(n, p, path)); break;
      case ValueKind::Bool: out.set(p.name, bool_value(n, p, path)); break;
      case ValueKind::String:
        if (!n.IsScalar()) fail(path, p.expected_text(), shown(n));
        out.set(p.name, n.Scalar());
        break;
      case ValueKind::Choice: out.set(p.name, choice_value(n, p, path)); break;
      case ValueKind::Vector3:
      case ValueKind::RealList: out.set(p.name, Teuchos::Array<double>(real_list(n, p, path))); break;
      case ValueKind::StringList: out.set(p.name, Teuchos::Array<std::string>(word_list(n, p, path))); break;
      case ValueKind::Section: {
        auto& sub = out.sublist(p.name);
        map_keys(n, p.children, path, sub);
        CheckContext ctx(file_, path, &marks_);
        for (const auto& c : p.checks) c(sub, ctx);
        break;
      }
      case ValueKind::Typed: typed_entry(n, *p.registry, path, out.sublist(p.name)); break;
      case ValueKind::Collection: collection(n, p, path, out.sublist(p.name)); break;
      case ValueKind::PassThrough:
        if (!n.IsMap()) fail(path, p.expected_text(), shown(n));
        generic(n, path, out.sublist(p.name));
        break;
      default:
        throw std::logic_error("scene validation: unknown value kind at " + path);
    }
  }

  int integer_value(const YAML::Node& n, const Param& p, const std::string& path) {
    if (!n.IsScalar()) fail(path, p.expected_text(), shown(n));
    long long v = 0;
    try {
      v = n.as<long long>();
    } catch (const YAML::Exception&) {
      fail(path, p.expected_text(), shown(n));
    }
    if (v > std::numeric_limits<int>::max() || v < std::numeric_limits<int>::min())
      fail(path, p.expected_text(), shown(n) + " (too large)");
    check_range(static_cast<double>(v), p, path, shown(n));
    return static_cast<int>(v);
  }

  bool bool_value(const YAML::Node& n, const Param& p, const std::string& path) {
    if (!n.IsScalar()) fail(path, p.expected_text(), shown(n));
    bool v = false;
    try {
      v = n.as<bool>();
    } catch (const YAML::Exception&) {
      fail(path, p.expected_text(), shown(n));
    }
    return v;
  }

  std::string choice_value(const YAML::Node& n, const Param& p, const std::string& path) {
    if (!n.IsScalar()) fail(path, p.expected_text(), shown(n));
    const std::string w = n.Scalar();
    if (std::find(p.choices.begin(), p.choices.end(), w) == p.choices.end())
      fail(path, p.expected_text(), shown(n) + suggestion(w, p.choices));
    return w;
  }

  std::vector<double> real_list(const YAML::Node& n, const Param& p, const std::string& path) {
    if (!n.IsSequence()) fail(path, p.expected_text(), shown(n));
    if (p.kind == ValueKind::Vector3 && n.size() != 3) fail(path, p.expected_text(), shown(n));
    std::vector<double> a;
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string ip = path + "[" + std::to_string(i) + "]";
      const double v = real_value(n[i], p, ip);
      check_range(v, p, ip, shown(n[i]));
      a.push_back(v);
    }
    return a;
  }

  std::vector<std::string> word_list(const YAML::Node& n, const Param& p, const std::string& path) {
    std::vector<std::string> a;
    if (n.IsScalar()) {
      // A single word is accepted as a one-element list.
      a.push_back(n.Scalar());
    } else if (n.IsSequence()) {
      for (size_t i = 0; i < n.size(); ++i) {
        if (!n[i].IsScalar()) fail(path + "[" + std::to_string(i) + "]", "a word", shown(n[i]));
        a.push_back(n[i].Scalar());
      }
    } else {
      fail(path, p.expected_text(), shown(n));
    }
    std::set<std::string> seen;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::string ip = path + "[" + std::to_string(i) + "]";
      if (!p.choices.empty() && std::find(p.choices.begin(), p.choices.end(), a[i]) == p.choices.end())
        fail(ip, "one of {" + list_words(p.choices) + "}", "'" + a[i] + "'" + suggestion(a[i], p.choices));
      if (!seen.insert(a[i]).second) fail(ip, "each word once", "'" + a[i] + "' again");
    }
    return a;
  }

  void collection(const YAML::Node& n, const Param& p, const std::string& path, ParameterList& sub) {
    if (!n.IsMap()) fail(path, p.expected_text() + " (name: {type: ..., ...})", shown(n));
    std::set<std::string> seen;
    for (const auto& kv : n) {
      const std::string name = kv.first.Scalar();
      const std::string ipath = join_path(path, name);
      record(ipath, kv.first);
      if (!seen.insert(name).second) fail(ipath, "each name once", "a second '" + name + "'");
      if (name.empty() || name.find_first_of("./ \t") != std::string::npos)
        fail(ipath, "a name without dots, slashes or spaces", "'" + name + "'");
      typed_entry(kv.second, *p.registry, ipath, sub.sublist(name));
    }
  }

  void typed_entry(const YAML::Node& n, const TypeRegistry& reg, const std::string& path, ParameterList& out) {
    const std::string a = std::string("aeiou").find(reg.category()[0]) == std::string::npos ? "a " : "an ";
    if (!n.IsMap()) fail(path, "a map with a 'type' key naming " + a + reg.category() + " type", shown(n));
    const YAML::Node t = n["type"];
    if (!t.IsDefined() || !t.IsScalar())
      fail(join_path(path, "type"), a + reg.category() + " type, one of {" + list_words(reg.names()) + "}",
           t.IsDefined() ? shown(t) : "nothing (the 'type' key is missing)");
    const std::string type = t.Scalar();
    const TypeInfo* info = reg.find(type);
    if (!info)
      fail(join_path(path, "type"), a + reg.category() + " type, one of {" + list_words(reg.names()) + "}",
           "'" + type + "'" + suggestion(type, reg.names()));
    out.set("type", type);
    map_keys(n, info->params, path, out, {"type"});
    CheckContext ctx(file_, path, &marks_);
    for (const auto& c : info->checks) c(out, ctx);
  }

  // Solver parameter lists: keep natural YAML types (int, double, bool, string).
  void generic(const YAML::Node& n, const std::string& path, ParameterList& out) {
    for (const auto& kv : n) {
      const std::string key = kv.first.Scalar();
      const std::string kpath = join_path(path, key);
      record(kpath, kv.first);
      const YAML::Node& v = kv.second;
      if (v.IsMap()) {
        generic(v, kpath, out.sublist(key));
      } else if (v.IsScalar()) {
        const std::string s = v.Scalar();
        long long i = 0;
        double d = 0.0;
        bool b = false;
        if (YAML::convert<long long>::decode(v, i) && s.find_first_of(".eE") == std::string::npos) {
          out.set(key, static_cast<int>(i));
        } else if (YAML::convert<double>::decode(v, d) && std::isfinite(d)) {
          out.set(key, d);
        } else if (YAML::convert<bool>::decode(v, b)) {
          out.set(key, b);
        } else {
          out.set(key, s);
        }
      } else {
        fail(kpath, "a value or a map", shown(v));
      }
    }
  }

 private:
  bool overridden(const std::string& path) const {
    for (const auto& [k, v] : marks_)
      if (v.first < 0 && (path == k || path.rfind(k + ".", 0) == 0 || path.rfind(k + "[", 0) == 0)) return true;
    return false;
  }
  std::string file_;
  Marks& marks_;
};

// Sets `value` (YAML text) at a dotted key path inside `root`, creating maps as needed.
// Returns the key path it set.
std::string apply_override(YAML::Node root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError("--set " + assignment + ": expected KEY.PATH=VALUE, found no '='");
  const std::string key = assignment.substr(0, eq);
  const std::string val = assignment.substr(eq + 1);
  YAML::Node value;
  try {
    value = YAML::Load(val);
  } catch (const YAML::Exception& e) {
    throw SceneError("--set " + key + ": expected a YAML value, found '" + val + "' (" + e.msg + ")");
  }
  std::vector<std::string> parts;
  std::stringstream ss(key);
  std::string part;
  while (std::getline(ss, part, '.')) {
    if (part.empty()) throw SceneError("--set " + key + ": expected KEY.PATH with non-empty parts, found '" + key + "'");
    parts.push_back(part);
  }
  std::vector<YAML::Node> chain{root};
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = chain.back()[parts[i]];
    if (next.IsDefined() && !next.IsNull() && !next.IsMap())
      throw SceneError("--set " + key + ": expected '" + parts[i] + "' to be a map of keys, found a value");
    if (!next.IsDefined() || next.IsNull()) {
      chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
      next = chain.back()[parts[i]];
    }
    chain.push_back(next);
  }
  chain.back()[parts.back()] = value;
  return key;
}

}  // namespace

namespace {

std::vector<std::string> key_names(const std::vector<Param>& keys, bool with_type) {
  std::vector<std::string> names;
  if (with_type) names.push_back("type");
  for (const auto& k : keys) names.push_back(k.name);
  return names;
}

const ParameterList* sublist_of(const ParameterList* list, const std::string& name) {
  return list && list->isSublist(name) ? &list->sublist(name) : nullptr;
}

// The keys of a typed entry `list` (its `type` chosen in the scene), or nullptr.
const TypeInfo* type_of(const ParameterList* list, const TypeRegistry& reg) {
  if (!list || !list->isType<std::string>("type")) return nullptr;
  return reg.find(list->get<std::string>("type"));
}

}  // namespace

std::string key_problem(const ValidatedTree& tree, const Param& root, const std::string& key) {
  std::vector<std::string> parts(1);
  for (char c : key) {
    if (c == '.') parts.emplace_back();
    else parts.back() += c;
  }
  for (const auto& p : parts)
    if (p.empty()) return "expected KEY.PATH with non-empty parts, found '" + key + "'";
  const std::vector<Param>* keys = &root.children;
  const ParameterList* list = tree.params.get();
  bool typed = false;  // the level is a typed entry: its `type` key is declared too
  std::string path;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    const bool last = i + 1 == parts.size();
    const std::vector<std::string> known = key_names(*keys, typed);
    if (typed && part == "type") return last ? "" : "expected a key path, found '" + key + "' ('type' holds a word)";
    const Param* p = nullptr;
    for (const auto& k : *keys)
      if (k.name == part) p = &k;
    if (!p)
      return "expected a key of " + (path.empty() ? std::string("the scene") : "'" + path + "'") + ", one of {" +
             list_words(known) + "}, found '" + part + "'" + suggestion(part, known);
    path = join_path(path, part);
    if (last) return "";
    list = sublist_of(list, part);
    switch (p->kind) {
      case ValueKind::Section: keys = &p->children; typed = false; break;
      case ValueKind::PassThrough: return "";  // handed to Trilinos unchanged: any key
      case ValueKind::Typed:
      case ValueKind::Collection: {
        if (p->kind == ValueKind::Collection) {
          const std::string& name = parts[++i];
          std::vector<std::string> names;
          if (list)
            for (const auto& e : *list) names.push_back(e.first);
          if (!sublist_of(list, name))
            return "expected one of the names of '" + path + "' in the scene {" + list_words(names) + "}, found '" +
                   name + "'" + suggestion(name, names);
          path = join_path(path, name);
          if (i + 1 == parts.size()) return "";
          list = sublist_of(list, name);
        }
        const TypeInfo* info = type_of(list, *p->registry);
        if (!info) return "expected a key of '" + path + "' with its type set in the scene, found '" + key + "'";
        keys = &info->params;
        typed = true;
        break;
      }
      default: return "expected '" + path + "' to be a section of keys, found a value (" + p->expected_text() + ")";
    }
  }
  return "";
}

[[noreturn]] void CheckContext::fail(const std::string& key, const std::string& expected, const std::string& found) const {
  const std::string p = key.empty() ? path_ : join_path(path_, key);
  throw SceneError(location(file_, marks_ ? *marks_ : Marks{}, p) + ": " + p + ": expected " + expected + ", found " + found);
}

ValidatedTree validate_yaml(const std::string& yaml_text, const std::string& file_name,
                            const std::vector<std::string>& overrides, const Param& root) {
  YAML::Node doc;
  try {
    doc = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw SceneError(file_name + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                     ": expected well-formed YAML, found a syntax error: " + e.msg);
  }
  if (doc.IsNull() || !doc.IsDefined()) doc = YAML::Node(YAML::NodeType::Map);
  if (!doc.IsMap())
    throw SceneError(file_name + ": (top level): expected a map of keys, found " + shown(doc));
  ValidatedTree tree;
  auto params = std::make_shared<ParameterList>("scene");
  for (const auto& o : overrides) {
    try {
      tree.marks[apply_override(doc, o)] = {-1, -1};
    } catch (const SceneError& e) {
      throw SceneError(file_name + ": " + e.what());
    }
  }
  Validator v(file_name, tree.marks);
  v.map_keys(doc, root.children, "", *params);
  CheckContext ctx(file_name, "", &tree.marks);
  for (const auto& c : root.checks) c(*params, ctx);
  tree.params = std::move(params);
  return tree;
}

// ---------------------------------------------------------------------------------------
// Description (traverse check)
// ---------------------------------------------------------------------------------------
namespace {

// A value as the validated scene shows it: the types validation stores (int, double, bool,
// string and the arrays of double and string).
std::string scalar_text(const Teuchos::ParameterEntry& e) {
  std::ostringstream os;
  os << std::setprecision(15);
  if (e.isType<double>()) {
    os << e.getValue<double>(nullptr);
  } else if (e.isType<int>()) {
    os << e.getValue<int>(nullptr);
  } else if (e.isType<bool>()) {
    os << (e.getValue<bool>(nullptr) ? "true" : "false");
  } else if (e.isType<std::string>()) {
    YAML::Emitter em;
    em << e.getValue<std::string>(nullptr);
    os << em.c_str();
  } else if (e.isType<Teuchos::Array<double>>()) {
    const auto& v = e.getValue<Teuchos::Array<double>>(nullptr);
    os << "[";
    for (Teuchos::Array<double>::size_type i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
    os << "]";
  } else if (e.isType<Teuchos::Array<std::string>>()) {
    const auto& v = e.getValue<Teuchos::Array<std::string>>(nullptr);
    os << "[";
    for (Teuchos::Array<std::string>::size_type i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
    os << "]";
  } else {
    throw std::logic_error("describe: a value of type " + e.getAny(false).typeName() + " in the scene");
  }
  return os.str();
}

std::string comment(const Param& p) {
  std::string c = p.doc;
  if (!p.units.empty()) c += " [" + p.units + "]";
  const std::string r = p.range_text();
  if (!r.empty()) c += "; " + r;
  if (p.accepts_auto) c += " or auto";
  if (p.default_text) c += "; default " + *p.default_text;
  else if (p.is_required) c += "; required";
  return c;
}

class Describer {
 public:
  explicit Describer(bool comments) : comments_(comments) {}
  std::ostringstream os;

  void line(int depth, const std::string& body, const std::string& note) {
    std::string s(2 * depth, ' ');
    s += body;
    if (comments_ && !note.empty()) {
      if (s.size() < 40) s.resize(40, ' ');
      s += "  # " + note;
    }
    os << s << "\n";
  }

  void keys(const ParameterList& list, const std::vector<Param>& params, int depth) {
    for (const auto& p : params) {
      if (!p.condition.first.empty() && !(list.isType<std::string>(p.condition.first) &&
                                          list.get<std::string>(p.condition.first) == p.condition.second))
        continue;
      const bool container = p.kind == ValueKind::Section || p.kind == ValueKind::Typed ||
                             p.kind == ValueKind::Collection || p.kind == ValueKind::PassThrough;
      if (!list.isParameter(p.name)) {
        if (comments_ && !container) line(depth, "# " + p.name + ":", comment(p) + "; unset");
        continue;
      }
      if (!container) {
        line(depth, p.name + ": " + scalar_text(*list.getEntryPtr(p.name)), comment(p));
        continue;
      }
      const auto& sub = list.sublist(p.name);
      switch (p.kind) {
        case ValueKind::Section:
          line(depth, p.name + ":", p.doc);
          keys(sub, p.children, depth + 1);
          break;
        case ValueKind::Typed:
          line(depth, p.name + ":", p.doc + types_note(*p.registry));
          typed(sub, *p.registry, depth + 1);
          break;
        case ValueKind::Collection:
          line(depth, p.name + (sub.numParams() == 0 ? ": {}" : ":"), p.doc + types_note(*p.registry));
          for (const auto& e : sub) {
            line(depth + 1, e.first + ":", "");
            typed(sub.sublist(e.first), *p.registry, depth + 2);
          }
          break;
        case ValueKind::PassThrough:
          line(depth, p.name + (sub.numParams() == 0 ? ": {}" : ":"), p.doc);
          generic(sub, depth + 1);
          break;
        default:
          throw std::logic_error("describe: unexpected kind");
      }
    }
  }

  std::string types_note(const TypeRegistry& r) {
    std::string s = " (" + r.category() + " types: ";
    const auto n = r.names();
    for (size_t i = 0; i < n.size(); ++i) s += (i ? ", " : "") + n[i];
    return s + ")";
  }

  void typed(const ParameterList& list, const TypeRegistry& r, int depth) {
    const std::string type = list.get<std::string>("type");
    const TypeInfo* info = r.find(type);
    line(depth, "type: " + type, info ? info->doc : "");
    if (info) keys(list, info->params, depth);
  }

  void generic(const ParameterList& list, int depth) {
    for (const auto& e : list) {
      const auto& name = e.first;
      if (e.second.isList()) {
        line(depth, name + ":", "");
        generic(list.sublist(name), depth + 1);
      } else {
        YAML::Emitter em;
        em << name;
        line(depth, std::string(em.c_str()) + ": " + scalar_text(e.second), "");
      }
    }
  }

 private:
  bool comments_;
};

}  // namespace

std::string describe(const ValidatedTree& tree, const Param& root, bool with_comments) {
  Describer d(with_comments);
  d.keys(*tree.params, root.children, 0);
  return d.os.str();
}

}  // namespace traverse::scene
