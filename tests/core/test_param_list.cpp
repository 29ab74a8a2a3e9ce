// traverse's parameter list (core/param_list.hpp): the validated scene and the solver settings.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "traverse/core/param_list.hpp"

namespace traverse {
namespace {

TEST(ParamList, KeepsTypesOrderAndSublists) {
  ParamList p("top");
  p.set("b", true);
  p.set("i", 3);
  p.set("d", 0.5);
  p.set("s", "text");  // a C string is stored as std::string
  p.set("v", std::vector<double>{1.0, 2.0});
  p.sublist("sub").set("x", 1);
  p.set("i", 4);  // replaced in place
  ASSERT_EQ(p.numParams(), 6u);
  std::vector<std::string> names;
  for (const auto& e : p.entries()) names.push_back(e.name());
  EXPECT_EQ(names, (std::vector<std::string>{"b", "i", "d", "s", "v", "sub"}));
  EXPECT_EQ(p.get<int>("i"), 4);
  EXPECT_EQ(p.get<std::string>("s"), "text");
  EXPECT_TRUE(p.isType<double>("d"));
  EXPECT_FALSE(p.isType<int>("d"));
  EXPECT_TRUE(p.isSublist("sub"));
  EXPECT_FALSE(p.isSublist("d"));
  EXPECT_EQ(p.sublist("sub").get<int>("x"), 1);
  EXPECT_EQ(p.get<double>("missing", 7.0), 7.0);
  EXPECT_FALSE(p.isParameter("missing"));  // a default is not stored
  // Copies are deep.
  ParamList q = p;
  q.sublist("sub").set("x", 2);
  EXPECT_EQ(p.sublist("sub").get<int>("x"), 1);
  EXPECT_NE(p, q);
  q.sublist("sub").set("x", 1);
  EXPECT_EQ(p, q);
  EXPECT_TRUE(q.remove("b"));
  EXPECT_FALSE(q.remove("b"));
  EXPECT_EQ(q.numParams(), 5u);
}

TEST(ParamList, WrongTypesAndMissingKeysAreNamed) {
  ParamList p("solver");
  p.set("Residual Tolerance", 1e-8);
  try {
    (void)p.get<int>("Residual Tolerance");
    ADD_FAILURE() << "a double was read as an int";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'Residual Tolerance' in 'solver' is a double, expected an int"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)p.get<double>("Nothing"), std::invalid_argument);
  EXPECT_THROW((void)static_cast<const ParamList&>(p).sublist("Nothing"), std::invalid_argument);
  EXPECT_THROW((void)p.sublist("Residual Tolerance"), std::invalid_argument);  // a value, not a sublist
  // A value of another type is an error even with a fallback.
  EXPECT_THROW((void)p.get<std::string>("Residual Tolerance", "x"), std::invalid_argument);
}

}  // namespace
}  // namespace traverse
