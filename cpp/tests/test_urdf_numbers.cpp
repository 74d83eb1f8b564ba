// URDF numbers: a non-numeric, non-finite or miscounted number attribute is refused with a
// UrdfError naming the link or joint and the attribute; finite spellings urdfdom reads still load.
#include <gtest/gtest.h>

#include <string>

#include "hovi/errors.hpp"
#include "hovi/parsers/urdf.hpp"

using namespace hovi;

namespace {

// A one-joint robot; `inertia` and `axis` are put in as written.
std::string robot(const std::string& inertia, const std::string& axis) {
  return "<robot name=\"r\"><link name=\"base\"/><link name=\"arm\"><inertial><mass value=\"1\"/><inertia " + inertia +
         "/></inertial></link><joint name=\"j\" type=\"continuous\"><parent link=\"base\"/><child link=\"arm\"/>"
         "<origin xyz=\"0 0 -1\"/><axis xyz=\"" + axis + "\"/></joint></robot>";
}

const std::string kInertia = "ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"";

std::string error_of(const std::string& xml) {
  try {
    model_from_urdf(xml);
  } catch (const UrdfError& e) {
    return e.what();
  }
  return "(loaded)";
}

TEST(UrdfNumbers, BadNumbersAreRefusedNamingTheElement) {
  EXPECT_EQ(error_of(robot("ixx=\"nan\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"", "1 0 0")),
            "link 'arm': <inertial><inertia ixx=\"nan\">: not a finite number of magnitude at most 1e12");
  EXPECT_EQ(error_of(robot("ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"1e999\" iyz=\"0\" izz=\"0.1\"", "1 0 0")),
            "link 'arm': <inertial><inertia iyy=\"1e999\">: not a finite number of magnitude at most 1e12");
  EXPECT_EQ(error_of(robot(kInertia, "1 -inf 0")),
            "joint 'j': <axis xyz=\"1 -inf 0\">: not 3 finite numbers of magnitude at most 1e12");
  EXPECT_EQ(error_of(robot(kInertia, "1 0")), "joint 'j': <axis xyz=\"1 0\">: not 3 finite numbers of magnitude at most 1e12");
  // finite but absurd lengths, masses and inertias would overflow the dynamics (found by bench/fuzz_urdf.py)
  EXPECT_EQ(error_of(robot("ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"1e308\"", "1 0 0")),
            "link 'arm': <inertial><inertia izz=\"1e308\">: not a finite number of magnitude at most 1e12");
}

TEST(UrdfNumbers, HugeLimitsAreMetadataAndLoad) {
  std::string xml = robot(kInertia, "1 0 0");
  xml.insert(xml.find("</joint>"), "<limit lower=\"-1e300\" upper=\"1e300\" effort=\"1e30\" velocity=\"1e20\"/>");
  EXPECT_EQ(model_from_urdf(xml).spec[0].limits.effort, 1e30);  // (a continuous joint: no position limits)
}

TEST(UrdfNumbers, FiniteSpellingsLoad) {
  const Model a = model_from_urdf(robot(kInertia, "1 0 0"));
  const Model b = model_from_urdf(robot("ixx=\"+0.1\" ixy=\"1e-400\" ixz=\" 0\" iyy=\"1E-1\" iyz=\"-0\" izz=\"0.1\"",
                                        " 1  0 0 "));
  EXPECT_EQ(a.n(), 1);
  EXPECT_EQ(b.n(), 1);
}

}  // namespace
