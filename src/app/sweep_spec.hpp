#pragma once
// What `traverse sweep` varies and reports (docs/sweeps.md): the --vary options, their
// cartesian product of cases, the --summary scalar. Parsing only; throws UsageError.
#include <string>
#include <vector>

namespace traverse::app {

/// One --vary KEY=SPEC (or --with KEY=SPEC): the key path and the values (YAML text, as
/// --set takes them).
struct VaryOption {
  std::string key;
  std::vector<std::string> values;
  bool with_previous = false;  ///< --with: varies together with the option before it (same count)
};

/// Parses "KEY=v1,v2,..." where each item is a YAML value or a range a:b:step (values
/// a + k step, k = 0, 1, ..., up to b within 1e-9 steps; printed with the decimals of a, b
/// and step when all three are plain decimals, else shortest round-trip). Commas inside
/// [...], {...} or quotes do not separate items. Throws UsageError naming `option`.
VaryOption parse_vary(const std::string& text, const std::string& option = "--vary");

/// The --set assignments ("key=value") of every case: the cartesian product of `options`,
/// the first option outermost (the last one varies fastest); a --with option takes the
/// value of the same index as the option it joins. Throws UsageError when the product has
/// more than `max_cases` cases, a key comes twice or a --with has another number of values.
std::vector<std::vector<std::string>> sweep_cases(const std::vector<VaryOption>& options, std::size_t max_cases);

/// --summary PROBE[.COMPONENT]:REDUCTION, e.g. midspan.y:min.
struct SummarySpec {
  enum class Reduction { min, max, absmax, mean, final };
  std::string text;       ///< as given (the index column's name); empty: no summary
  std::string probe;
  int component = -1;     ///< 0, 1, 2 for .x, .y, .z; -1: none given (one-component probes)
  Reduction reduction = Reduction::min;
  bool given() const { return !text.empty(); }
};
SummarySpec parse_summary(const std::string& text);

/// The reduction of one probe's values (NaN entries skipped; NaN when none is left).
double reduce(const std::vector<double>& values, SummarySpec::Reduction r);

}  // namespace traverse::app
