#pragma once
// Declarative scene schema: every key a scene may hold is declared once, in code, with its
// meaning, units, range and default. Validation walks a parsed YAML document against the
// schema at full depth and produces a typed Teuchos::ParameterList (a real number is a double,
// a whole number an int, a list of numbers a Teuchos::Array<double>, a list of words a
// Teuchos::Array<std::string>, a section a sublist); any problem is a SceneError naming the
// file, the line, the key path, what was expected and what was found.
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

// Declared only: Teuchos_ParameterList.hpp stays out of the many files that include the scene.
namespace Teuchos {
class ParameterList;
}

namespace traverse::scene {

/// A number as scene messages show it (up to 12 significant digits).
std::string format_number(double v);

/// Bad input: the message names the file, the key path, what was expected and what was found.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class ValueKind {
  Real,         ///< finite double (integers accepted)
  Integer,      ///< whole number
  Bool,         ///< true / false
  String,       ///< free text
  Choice,       ///< one of a fixed set of words
  Vector3,      ///< [x, y, z] of finite doubles
  RealList,     ///< [a, b, ...] of finite doubles
  StringList,   ///< [a, b, ...] of words (optionally restricted to a set)
  Section,      ///< nested map with its own declared keys
  Typed,        ///< nested map whose `type` key selects the declared keys from a registry
  Collection,   ///< map of user-chosen names to Typed entries of one registry
  PassThrough,  ///< nested map handed unchanged to a Trilinos package (NOX, Stratimikos, LOCA)
};

class TypeRegistry;
class CheckContext;

/// A check on a validated section (contradictions, cross-key conditions). It reports a
/// problem through CheckContext::fail, which throws.
using Check = std::function<void(const Teuchos::ParameterList& section, const CheckContext& ctx)>;

/// One declared key. Built fluently: real("length", "Beam length", "m").positive().required().
struct Param {
  std::string name;
  ValueKind kind = ValueKind::Real;
  std::string doc;
  std::string units;
  bool is_required = false;
  std::optional<std::string> default_text;  ///< YAML text of the default value
  bool accepts_auto = false;                 ///< the word `auto` is accepted (stored as string)
  bool omit_when_absent = false;             ///< Section: absent means absent (no defaults filled)
  /// Applies only when the sibling key `first` (validated earlier) has the value `second`;
  /// otherwise the key must be absent. Empty: always applies.
  std::pair<std::string, std::string> condition;
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  std::vector<std::string> choices;  ///< Choice / StringList vocabulary
  std::vector<Param> children;       ///< Section keys
  std::vector<Check> checks;         ///< Section checks
  std::shared_ptr<const TypeRegistry> registry;  ///< Typed / Collection

  Param& required();
  Param& def(const std::string& yaml_text);
  Param& def(double value);
  Param& allow_auto();
  Param& only_if_given();        ///< Section: validated only when present in the file
  Param& when(const std::string& sibling, const std::string& value);  ///< see `condition`
  Param& positive();             ///< > 0
  Param& non_negative();         ///< >= 0
  Param& at_least(double v);     ///< >= v
  Param& above(double v);        ///< > v
  Param& at_most(double v);      ///< <= v
  Param& below(double v);        ///< < v
  Param& add(const Param& child);  ///< Section: add a key
  Param& check(Check c);           ///< Section: add a check

  /// Human-readable range, e.g. "> 0", "in [0, 1]", "one of {a, b}". Empty if unrestricted.
  std::string range_text() const;
  /// What a value must be, e.g. "a real number > 0" (used in error messages).
  std::string expected_text() const;
};

Param real(const std::string& name, const std::string& doc, const std::string& units = "");
Param integer(const std::string& name, const std::string& doc);
Param boolean(const std::string& name, const std::string& doc);
Param text(const std::string& name, const std::string& doc);
Param choice(const std::string& name, const std::string& doc, std::vector<std::string> words);
Param vector3(const std::string& name, const std::string& doc, const std::string& units = "");
Param real_list(const std::string& name, const std::string& doc, const std::string& units = "");
Param word_list(const std::string& name, const std::string& doc, std::vector<std::string> words = {});
Param section(const std::string& name, const std::string& doc);
Param typed(const std::string& name, const std::string& doc, std::shared_ptr<const TypeRegistry> r);
Param collection(const std::string& name, const std::string& doc, std::shared_ptr<const TypeRegistry> r);
Param pass_through(const std::string& name, const std::string& doc);

/// One type of a category (an end condition, a load, a probe...): its documentation and keys.
struct TypeInfo {
  std::string name;
  std::string doc;
  std::vector<Param> params;
  std::vector<Check> checks;
};

/// Maps type names of one category to their declared keys.
class TypeRegistry {
 public:
  explicit TypeRegistry(std::string category) : category_(std::move(category)) {}
  TypeRegistry& add(TypeInfo info);
  const TypeInfo* find(const std::string& name) const;
  std::vector<std::string> names() const;
  const std::string& category() const { return category_; }

 private:
  std::string category_;
  std::map<std::string, TypeInfo> types_;
};

/// Reports a failed check with the position of the offending key.
class CheckContext {
 public:
  CheckContext(std::string file, std::string path, const std::map<std::string, std::pair<int, int>>* marks)
      : file_(std::move(file)), path_(std::move(path)), marks_(marks) {}
  /// Throws SceneError "<file>:<line>:<col>: <path>.<key>: expected <expected>, found <found>".
  [[noreturn]] void fail(const std::string& key, const std::string& expected, const std::string& found) const;
  const std::string& path() const { return path_; }

 private:
  std::string file_;
  std::string path_;
  const std::map<std::string, std::pair<int, int>>* marks_;
};

/// A validated scene: the typed parameter list and where each key came from.
struct ValidatedTree {
  /// Set once by validate_yaml and never changed: copies of a tree share it.
  std::shared_ptr<const Teuchos::ParameterList> params;
  std::map<std::string, std::pair<int, int>> marks;  ///< key path -> (line, column), 1-based; (-1, -1): set by --set
};

/// Parses YAML text (file name used in messages), applies `overrides` ("a.b.c=value", value
/// in YAML syntax) and validates against `root` (a Section). Throws SceneError.
ValidatedTree validate_yaml(const std::string& yaml_text, const std::string& file_name,
                            const std::vector<std::string>& overrides, const Param& root);

/// Empty if `key` ("a.b.c", as --set takes it) is a key the schema declares at that place
/// of the validated scene `tree` (typed entries resolved by their type in the tree, names
/// of collections taken from the tree, anything below a pass-through section); otherwise
/// "expected ..., found ..." saying what is known there.
std::string key_problem(const ValidatedTree& tree, const Param& root, const std::string& key);

/// The complete validated scene as YAML, every default filled in, each key followed by a
/// comment with its meaning, units, range and default; optional keys left unset appear as
/// comments. With `with_types`, each registry's other types are listed too.
std::string describe(const ValidatedTree& tree, const Param& root, bool with_comments = true);

}  // namespace traverse::scene
