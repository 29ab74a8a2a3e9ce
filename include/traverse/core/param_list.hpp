#pragma once
// A nested list of named, typed values in the order they were set: the validated scene tree and
// the rod solver's settings. Trilinos-free, so that a run in one process (the executable
// traverse) links no Trilinos library at all; the Trilinos side converts it where a package
// takes a Teuchos::ParameterList (solver/teuchos_params.hpp).
//
// Its interface is the subset of Teuchos::ParameterList's that traverse uses, under the same
// names (get, set, sublist, isParameter, isSublist, isType, numParams), so that code reads the
// same on both sides. Differences: values are strictly one of the types below (a C string is
// stored as std::string; lists are std::vector); get with a default does not store the default;
// documentation strings are not kept.
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace traverse {

class ParamList {
 public:
  /// A value that is not a sublist.
  using Value = std::variant<bool, int, double, std::string, std::vector<double>, std::vector<std::string>>;

  /// One entry: a value or a sublist.
  class Entry {
   public:
    Entry(std::string name, Value value) : name_(std::move(name)), value_(std::move(value)) {}
    Entry(std::string name, const ParamList& list)
        : name_(std::move(name)), list_(std::make_unique<ParamList>(list)) {}
    Entry(const Entry& o) : name_(o.name_), value_(o.value_), list_(o.list_ ? std::make_unique<ParamList>(*o.list_) : nullptr) {}
    Entry(Entry&&) noexcept = default;
    Entry& operator=(const Entry& o) {
      if (this != &o) *this = Entry(o);
      return *this;
    }
    Entry& operator=(Entry&&) noexcept = default;

    const std::string& name() const { return name_; }
    bool is_list() const { return list_ != nullptr; }
    const Value& value() const { return value_; }  ///< meaningless for a sublist
    const ParamList& list() const { return *list_; }  ///< only for a sublist

   private:
    friend class ParamList;
    std::string name_;
    Value value_;
    std::unique_ptr<ParamList> list_;
  };

  ParamList() = default;
  explicit ParamList(std::string name) : name_(std::move(name)) {}

  const std::string& name() const { return name_; }

  /// The name of Value's alternative `index` as messages show it: "bool", "int", "double",
  /// "string", "list of numbers", "list of words".
  static const char* value_type_name(std::size_t index);

  /// Sets (replaces, keeping its place) or appends the value of `key`.
  template <class T>
  void set(const std::string& key, T value) {
    static_assert(is_value<T>, "ParamList::set: bool, int, double, std::string or std::vector of double or string");
    put(key, Value(std::move(value)));
  }
  void set(const std::string& key, const char* value) { put(key, Value(std::string(value))); }

  /// The value of `key`; std::invalid_argument when it is missing, a sublist or another type.
  template <class T>
  const T& get(const std::string& key) const {
    static_assert(is_value<T>, "ParamList::get: bool, int, double, std::string or std::vector of double or string");
    const Entry* e = find(key);
    if (!e) missing(key);
    if (e->is_list() || !std::holds_alternative<T>(e->value_)) wrong_type(*e, type_name<T>());
    return std::get<T>(e->value_);
  }
  /// The value of `key`, or `fallback` when there is none (it is not stored); a value of
  /// another type is still an error.
  template <class T>
  T get(const std::string& key, const T& fallback) const {
    return isParameter(key) ? get<T>(key) : fallback;
  }
  std::string get(const std::string& key, const char* fallback) const { return get<std::string>(key, std::string(fallback)); }

  /// Whether `key` holds anything (a value or a sublist).
  bool isParameter(const std::string& key) const { return find(key) != nullptr; }
  bool isSublist(const std::string& key) const {
    const Entry* e = find(key);
    return e && e->is_list();
  }
  template <class T>
  bool isType(const std::string& key) const {
    const Entry* e = find(key);
    return e && !e->is_list() && std::holds_alternative<T>(e->value_);
  }

  /// The sublist `key`; std::invalid_argument when there is none.
  const ParamList& sublist(const std::string& key) const;
  /// The sublist `key`, created (empty) when there is nothing there; std::invalid_argument
  /// when `key` holds a value.
  ParamList& sublist(const std::string& key);

  /// The entry `key`; std::invalid_argument when there is none.
  const Entry& entry(const std::string& key) const {
    const Entry* e = find(key);
    if (!e) missing(key);
    return *e;
  }

  std::size_t numParams() const { return entries_.size(); }
  /// Removes `key`; whether it was there.
  bool remove(const std::string& key);
  /// The entries in the order they were first set.
  const std::vector<Entry>& entries() const { return entries_; }
  std::vector<Entry>::const_iterator begin() const { return entries_.begin(); }
  std::vector<Entry>::const_iterator end() const { return entries_.end(); }

  /// The same names, values and sublists in the same order (the lists' own names aside).
  bool operator==(const ParamList& o) const;
  bool operator!=(const ParamList& o) const { return !(*this == o); }

 private:
  template <class T>
  static constexpr bool is_value = std::is_same_v<T, bool> || std::is_same_v<T, int> || std::is_same_v<T, double> ||
                                   std::is_same_v<T, std::string> || std::is_same_v<T, std::vector<double>> ||
                                   std::is_same_v<T, std::vector<std::string>>;
  /// The index of T among Value's alternatives.
  template <class T, std::size_t I = 0>
  static constexpr std::size_t index_of() {
    if constexpr (std::is_same_v<T, std::variant_alternative_t<I, Value>>) return I;
    else return index_of<T, I + 1>();
  }
  template <class T>
  static const char* type_name() { return value_type_name(index_of<T>()); }
  const Entry* find(const std::string& key) const;
  Entry* find(const std::string& key);
  void put(const std::string& key, Value v);
  [[noreturn]] void missing(const std::string& key) const;
  [[noreturn]] void wrong_type(const Entry& e, const char* wanted) const;

  std::string name_;
  std::vector<Entry> entries_;
};

/// The type of an entry as messages show it: "bool", "int", "double", "string", "list of
/// numbers", "list of words" or "sublist".
std::string type_name_of(const ParamList::Entry& e);
/// "a " or "an " before `noun` ("an int", "a double").
std::string with_article(const std::string& noun);

}  // namespace traverse
