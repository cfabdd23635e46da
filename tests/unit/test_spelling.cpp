// Near spellings: a misspelt key is named with the key it most likely
// meant, and a required key's misspelling is reported before its absence.
#include <gtest/gtest.h>

#include "io/case_file.hpp"
#include "io/spelling.hpp"

#include "temp_file.hpp"

using namespace rpfem;

TEST(Spelling, EditDistanceCountsSwapsAsOne) {
  EXPECT_EQ(edit_distance("height", "heigth"), 1);
  EXPECT_EQ(edit_distance("nx", "nxx"), 1);
  EXPECT_EQ(edit_distance("width", "height"), 4);
  EXPECT_EQ(edit_distance("", "abc"), 3);
}

TEST(Spelling, NearestWithinTwoEditsAndHalfTheLetters) {
  EXPECT_EQ(nearest_spelling("heigth", {"width", "height", "nx"}), "height");
  EXPECT_EQ(nearest_spelling("output_evry", {"output_every", "max_cuts"}), "output_every");
  EXPECT_EQ(nearest_spelling("ny", {"nx"}), "");         // one edit of two letters: no guess
  EXPECT_EQ(nearest_spelling("height", {"height"}), "");  // itself: nothing to suggest
  EXPECT_EQ(nearest_spelling("radius", {"width"}), "");
}

TEST(Spelling, MisspeltRequiredKeyIsNamedBeforeItsAbsence) {
  CaseFile f(unit::write_temp("sp1.toml", "[a]\nheigth = 2.0\n"));
  auto a = f.root().required_table("a");
  try {
    a.real("height", std::nullopt, Range::positive(), "mm");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'a.heigth' (misspelt?); did you mean 'height'?"),
              std::string::npos)
        << e.what();
  }
}

TEST(Spelling, UnknownKeySuggestsTheKeyReadBesideIt) {
  CaseFile f(unit::write_temp("sp2.toml", "[a]\nmax_cust = 3\n"));
  auto a = f.root().required_table("a");
  EXPECT_EQ(a.integer("max_cuts", 6, 0, 30), 6);
  try {
    f.finish();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'a.max_cust'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("did you mean 'max_cuts'?"), std::string::npos) << e.what();
  }
}
