#include "traverse/core/param_list.hpp"

#include <iterator>

namespace traverse {

const char* ParamList::value_type_name(std::size_t index) {
  static const char* const names[] = {"bool", "int", "double", "string", "list of numbers", "list of words"};
  static_assert(std::size(names) == std::variant_size_v<Value>, "one name per alternative");
  return names[index];
}

std::string with_article(const std::string& noun) {
  return (!noun.empty() && std::string("aeiou").find(noun[0]) != std::string::npos ? "an " : "a ") + noun;
}

std::string type_name_of(const ParamList::Entry& e) {
  return e.is_list() ? "sublist" : ParamList::value_type_name(e.value().index());
}

const ParamList::Entry* ParamList::find(const std::string& key) const {
  for (const Entry& e : entries_)
    if (e.name_ == key) return &e;
  return nullptr;
}

ParamList::Entry* ParamList::find(const std::string& key) {
  for (Entry& e : entries_)
    if (e.name_ == key) return &e;
  return nullptr;
}

void ParamList::put(const std::string& key, Value v) {
  if (Entry* e = find(key)) {
    e->list_.reset();
    e->value_ = std::move(v);
    return;
  }
  entries_.emplace_back(key, std::move(v));
}

const ParamList& ParamList::sublist(const std::string& key) const {
  const Entry* e = find(key);
  if (!e) missing(key);
  if (!e->is_list()) wrong_type(*e, "sublist");
  return *e->list_;
}

ParamList& ParamList::sublist(const std::string& key) {
  Entry* e = find(key);
  if (!e) {
    entries_.emplace_back(key, ParamList(key));
    return *entries_.back().list_;
  }
  if (!e->is_list()) wrong_type(*e, "sublist");
  return *e->list_;
}

bool ParamList::remove(const std::string& key) {
  for (auto it = entries_.begin(); it != entries_.end(); ++it)
    if (it->name_ == key) {
      entries_.erase(it);
      return true;
    }
  return false;
}

bool ParamList::operator==(const ParamList& o) const {
  if (entries_.size() != o.entries_.size()) return false;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const Entry &a = entries_[i], &b = o.entries_[i];
    if (a.name_ != b.name_ || a.is_list() != b.is_list()) return false;
    if (a.is_list() ? !(*a.list_ == *b.list_) : a.value_ != b.value_) return false;
  }
  return true;
}

void ParamList::missing(const std::string& key) const {
  throw std::invalid_argument("parameter '" + key + "' is missing" + (name_.empty() ? "" : " in '" + name_ + "'"));
}

void ParamList::wrong_type(const Entry& e, const char* wanted) const {
  throw std::invalid_argument("parameter '" + e.name_ + "'" + (name_.empty() ? "" : " in '" + name_ + "'") +
                              " is " + with_article(type_name_of(e)) + ", expected " + with_article(wanted));
}

}  // namespace traverse
