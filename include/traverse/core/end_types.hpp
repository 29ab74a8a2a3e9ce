#pragma once
// The end conditions of the rod, declared once (docs/developer.md, "Where to add things"):
// each type's scene word, documentation and parameters, with where each parameter goes in
// EndSpec. The scene module builds the schema's `ends.left` / `ends.right` registry, its
// checks and the reading of an end from this table (scene.cpp, `end_types()`, `read_end`);
// the rod module keys its rows by EndType (rod/end_condition.cpp: dynamic rows, static rows
// and the conversion from EndSpec). Plain data on core types: no scene or rod header here.
#include <vector>

#include "traverse/core/types.hpp"

namespace traverse {

/// The end condition types, in the order of end_type_declarations().
enum class EndType { clamped, pinned, sliding, roller, free, prescribed };

/// One end condition of the rod as a scene gives it (fixed-frame vectors): the union of the
/// parameters of every type, each type reading the ones it declares.
struct EndSpec {
  EndType type = EndType::clamped;
  Vec3 axis = Vec3::UnitX();        ///< pin axis (pinned, roller) or sliding axis (sliding)
  Vec3 slide_axis = Vec3::UnitZ();  ///< roller: sliding axis
  double axial_force = 0.0;         ///< roller: external force along the sliding axis [N]
  Vec3 velocity = Vec3::Zero();     ///< prescribed end velocity [m/s]
  Vec3 rotation_rate = Vec3::Zero();  ///< prescribed end rotation rate [rad/s]
};

/// One parameter of an end condition type: a fixed-frame vector (`vector` set) or a real
/// number (`number` set), with its default.
struct EndParameter {
  const char* key;
  const char* doc;
  const char* units = "";
  Vec3 EndSpec::*vector = nullptr;
  double EndSpec::*number = nullptr;
  const char* vector_default = "[0, 0, 0]";  ///< as the scene writes it
  double number_default = 0.0;
  /// A direction: refused when zero ("a non-zero axis"), normalised when read.
  bool direction = false;
};

/// Two direction parameters that must be perpendicular: `key` is refused (located at it)
/// when its dot product with `other` exceeds 1e-12 of their norms' product.
struct EndPerpendicular {
  const char* key;
  const char* other;
  const char* expected;  ///< what the error says was expected
};

struct EndTypeDeclaration {
  EndType type;
  const char* word;  ///< the scene word
  const char* doc;
  std::vector<EndParameter> parameters;
  std::vector<EndPerpendicular> perpendicular;
};

/// Every end condition type, in enumerator order.
inline const std::vector<EndTypeDeclaration>& end_type_declarations() {
  using S = EndSpec;
  static const std::vector<EndTypeDeclaration> table{
      {EndType::clamped, "clamped", "Position and orientation fixed: u = 0, omega = 0", {}, {}},
      {EndType::pinned, "pinned",
       "Pin joint: position fixed, rotation only about the pin axis, no moment about it "
       "(u = 0, omega parallel to the axis, m . axis = 0)",
       {{"axis", "Pin axis, fixed frame", "", &S::axis, nullptr, "[1, 0, 0]", 0.0, true}},
       {}},
      {EndType::sliding, "sliding",
       "Clamped and sliding along an axis: no rotation, no motion across the axis, no force "
       "along it (u x axis = 0, omega = 0, n . axis = 0)",
       {{"axis", "Sliding axis, fixed frame", "", &S::axis, nullptr, "[0, 0, 1]", 0.0, true}},
       {}},
      {EndType::roller, "roller",
       "Pin joint that slides: rotation only about the pin axis, motion only along the sliding "
       "axis, a given external force along it, no moment about the pin axis",
       {{"axis", "Pin axis, fixed frame", "", &S::axis, nullptr, "[1, 0, 0]", 0.0, true},
        {"slide_axis", "Sliding axis, fixed frame (perpendicular to the pin axis)", "", &S::slide_axis, nullptr,
         "[0, 0, 1]", 0.0, true},
        {"force", "External force on the end along the sliding axis (negative: compression at the right end)", "N",
         nullptr, &S::axial_force, "", 0.0, false}},
       {{"slide_axis", "axis", "a sliding axis perpendicular to the pin axis"}}},
      {EndType::free, "free", "Free end: n = 0, m = 0", {}, {}},
      {EndType::prescribed, "prescribed", "Prescribed end velocity and rotation rate (constant, fixed frame)",
       {{"velocity", "End velocity", "m/s", &S::velocity, nullptr, "[0, 0, 0]", 0.0, false},
        {"rotation_rate", "End rotation rate", "rad/s", &S::rotation_rate, nullptr, "[0, 0, 0]", 0.0, false}},
       {}},
  };
  return table;
}

}  // namespace traverse
