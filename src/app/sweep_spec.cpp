#include "sweep_spec.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>

#include "cli.hpp"

namespace traverse::app {

namespace {

// Splits at commas outside brackets, braces and quotes.
std::vector<std::string> split_items(const std::string& s) {
  std::vector<std::string> out(1);
  int depth = 0;
  char quote = 0;
  for (char c : s) {
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    } else if (c == ',' && depth == 0) {
      out.emplace_back();
      continue;
    }
    out.back() += c;
  }
  return out;
}

bool parse_number(const std::string& s, double& x) {
  char* end = nullptr;
  x = std::strtod(s.c_str(), &end);
  return !s.empty() && *end == '\0' && std::isfinite(x);
}

// Decimals of a plain decimal number ("0.25" -> 2, "3" -> 0); -1 with an exponent.
int decimals(const std::string& s) {
  if (s.find_first_of("eE") != std::string::npos) return -1;
  const auto dot = s.find('.');
  return dot == std::string::npos ? 0 : static_cast<int>(s.size() - dot - 1);
}

std::string shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// A range a:b:step (exactly three numbers), appended to `values`; false if `item` is not one.
bool expand_range(const std::string& option, const std::string& key, const std::string& item, std::vector<std::string>& values) {
  std::vector<std::string> parts(1);
  for (char c : item) {
    if (c == ':') parts.emplace_back();
    else parts.back() += c;
  }
  if (parts.size() == 1) return false;
  double a = 0, b = 0, step = 0;
  const std::string what = option + " " + key + ": expected a value or a range a:b:step of three numbers";
  if (parts.size() != 3 || !parse_number(parts[0], a) || !parse_number(parts[1], b) || !parse_number(parts[2], step))
    throw UsageError{what + ", found '" + item + "'"};
  if (step == 0.0 || (b - a) * step < 0.0)
    throw UsageError{what + " with a step that leads from a to b (non-zero, of the sign of b - a), found '" + item + "'"};
  const double steps = (b - a) / step;
  if (!(steps <= 1e6)) throw UsageError{what + " of at most 10^6 steps, found '" + item + "' (" + shortest(steps) + ")"};
  const long last = static_cast<long>(std::floor(steps + 1e-9));
  int d = 0;
  for (const auto& p : parts) d = decimals(p) < 0 || d < 0 ? -1 : std::max(d, decimals(p));
  for (long k = 0; k <= last; ++k) {
    const double v = a + static_cast<double>(k) * step;
    if (d < 0) {
      values.push_back(shortest(v));
    } else {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.*f", d, v);
      values.push_back(std::string(buf) == "-0" ? "0" : buf);
    }
  }
  return true;
}

}  // namespace

VaryOption parse_vary(const std::string& text, const std::string& option) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw UsageError{option + " " + text + ": expected KEY.PATH=v1,v2,... or KEY.PATH=a:b:step, found no '='"};
  VaryOption o;
  o.key = text.substr(0, eq);
  if (o.key.front() == '.' || o.key.back() == '.' || o.key.find("..") != std::string::npos)
    throw UsageError{option + " " + o.key + ": expected KEY.PATH with non-empty parts, found '" + o.key + "'"};
  const std::string spec = text.substr(eq + 1);
  for (const auto& item : split_items(spec)) {
    if (item.empty())
      throw UsageError{option + " " + o.key + ": expected a comma-separated list of values or ranges a:b:step, found an "
                       "empty item in '" + spec + "'"};
    const bool braced = item.find_first_of("[{'\"") != std::string::npos;
    if (braced || !expand_range(option, o.key, item, o.values)) o.values.push_back(item);
  }
  return o;
}

std::vector<std::vector<std::string>> sweep_cases(const std::vector<VaryOption>& options, std::size_t max_cases) {
  if (options.empty()) throw UsageError{"'sweep': expected at least one --vary KEY=v1,v2,..., found none"};
  if (options.front().with_previous)
    throw UsageError{"--with " + options.front().key + ": expected a --vary before it to vary with, found none"};
  std::set<std::string> keys;
  std::vector<std::vector<const VaryOption*>> groups;  // a --vary and the --with options after it
  double count = 1.0;
  for (const auto& o : options) {
    if (!keys.insert(o.key).second) throw UsageError{"--vary " + o.key + ": expected each key once, found it again"};
    if (o.with_previous) {
      const VaryOption& lead = *groups.back().front();
      if (o.values.size() != lead.values.size())
        throw UsageError{"--with " + o.key + ": expected " + std::to_string(lead.values.size()) + " values, as many as --vary " +
                         lead.key + ", found " + std::to_string(o.values.size())};
      groups.back().push_back(&o);
      continue;
    }
    groups.push_back({&o});
    count *= static_cast<double>(o.values.size());
  }
  if (count > static_cast<double>(max_cases))
    throw UsageError{"--vary: expected at most " + std::to_string(max_cases) + " cases in all, found " + shortest(count)};
  std::vector<std::vector<std::string>> cases(1);
  for (const auto& g : groups) {
    std::vector<std::vector<std::string>> next;
    for (const auto& c : cases)
      for (std::size_t v = 0; v < g.front()->values.size(); ++v) {
        next.push_back(c);
        for (const VaryOption* o : g) next.back().push_back(o->key + "=" + o->values[v]);
      }
    cases.swap(next);
  }
  return cases;
}

SummarySpec parse_summary(const std::string& text) {
  const std::string what = "--summary: expected PROBE[.x|.y|.z]:REDUCTION with REDUCTION one of {min, max, absmax, "
                           "mean, final}, found '" + text + "'";
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) throw UsageError{what};
  SummarySpec s;
  s.text = text;
  const std::string red = text.substr(colon + 1);
  using R = SummarySpec::Reduction;
  if (red == "min") s.reduction = R::min;
  else if (red == "max") s.reduction = R::max;
  else if (red == "absmax") s.reduction = R::absmax;
  else if (red == "mean") s.reduction = R::mean;
  else if (red == "final") s.reduction = R::final;
  else throw UsageError{what};
  s.probe = text.substr(0, colon);
  const auto dot = s.probe.rfind('.');
  if (dot != std::string::npos) {
    const std::string comp = s.probe.substr(dot + 1);
    if (comp != "x" && comp != "y" && comp != "z") throw UsageError{what};
    s.component = comp[0] - 'x';
    s.probe = s.probe.substr(0, dot);
  }
  if (s.probe.empty()) throw UsageError{what};
  return s;
}

double reduce(const std::vector<double>& values, SummarySpec::Reduction r) {
  using R = SummarySpec::Reduction;
  double acc = std::numeric_limits<double>::quiet_NaN();
  std::size_t n = 0;
  for (double v : values) {
    if (std::isnan(v)) continue;
    ++n;
    switch (r) {
      case R::min: acc = n == 1 ? v : std::min(acc, v); break;
      case R::max: acc = n == 1 ? v : std::max(acc, v); break;
      case R::absmax: acc = n == 1 ? std::abs(v) : std::max(acc, std::abs(v)); break;
      case R::mean: acc = n == 1 ? v : acc + v; break;
      case R::final: acc = v; break;
      default: throw std::logic_error("reduce: reduction not handled");
    }
  }
  if (r == R::mean && n > 0) acc /= static_cast<double>(n);
  return acc;
}

}  // namespace traverse::app
