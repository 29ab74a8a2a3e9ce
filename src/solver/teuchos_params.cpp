#include "traverse/solver/teuchos_params.hpp"

#include <stdexcept>
#include <type_traits>
#include <variant>

namespace traverse::solver {

Teuchos::ParameterList to_teuchos(const ParamList& list) {
  Teuchos::ParameterList out(list.name());
  for (const auto& e : list.entries()) {
    if (e.is_list()) {
      out.sublist(e.name()) = to_teuchos(e.list());
      out.sublist(e.name()).setName(e.name());
      continue;
    }
    std::visit(
        [&](const auto& v) {
          using T = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<T, std::vector<double>> || std::is_same_v<T, std::vector<std::string>>)
            out.set(e.name(), Teuchos::Array<typename T::value_type>(v.begin(), v.end()));
          else
            out.set(e.name(), v);
        },
        e.value());
  }
  return out;
}

ParamList from_teuchos(const Teuchos::ParameterList& list) {
  ParamList out(list.name());
  for (auto it = list.begin(); it != list.end(); ++it) {
    const std::string& name = list.name(it);
    const Teuchos::ParameterEntry& e = list.entry(it);
    if (e.isList()) {
      out.sublist(name) = from_teuchos(list.sublist(name));
    } else if (e.isType<bool>()) {
      out.set(name, e.getValue<bool>(nullptr));
    } else if (e.isType<int>()) {
      out.set(name, e.getValue<int>(nullptr));
    } else if (e.isType<double>()) {
      out.set(name, e.getValue<double>(nullptr));
    } else if (e.isType<std::string>()) {
      out.set(name, e.getValue<std::string>(nullptr));
    } else if (e.isType<Teuchos::Array<double>>()) {
      const auto& a = e.getValue<Teuchos::Array<double>>(nullptr);
      out.set(name, std::vector<double>(a.begin(), a.end()));
    } else if (e.isType<Teuchos::Array<std::string>>()) {
      const auto& a = e.getValue<Teuchos::Array<std::string>>(nullptr);
      out.set(name, std::vector<std::string>(a.begin(), a.end()));
    } else {
      throw std::invalid_argument("from_teuchos: parameter '" + name + "' of '" + list.name() +
                                  "' has a type a traverse parameter list cannot hold");
    }
  }
  return out;
}

}  // namespace traverse::solver
