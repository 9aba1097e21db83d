#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cleanslam/readers/yaml_document.hpp"

namespace y = cleanslam::readers::yaml;

namespace {

const char* kSensors = R"(camera:
  width: 320
  fx: 280.5
  distortion: [0.1, -0.2, 0.0, 1e-3]
  T:
    - 1
    - 2
  name: "cam0"
  flag: true
wheels:
  wheel_base: 0.235
  extra: 3
)";

}  // namespace

TEST(YamlDocument, ParsesTreeWithLocations) {
  auto doc = y::parse_string(kSensors, "sensors.yaml");
  ASSERT_TRUE(doc.ok()) << doc.error();
  ASSERT_TRUE(doc->is_mapping());
  ASSERT_EQ(doc->entries.size(), 2U);
  const y::Node* camera = doc->find("camera");
  ASSERT_NE(camera, nullptr);
  const y::Node* fx = camera->find("fx");
  ASSERT_NE(fx, nullptr);
  EXPECT_EQ(fx->scalar, "280.5");
  EXPECT_EQ(fx->location.line, 3);
  EXPECT_EQ(fx->location.column, 7);
  EXPECT_EQ(fx->location.file_name(), "sensors.yaml");
  const y::Node* dist = camera->find("distortion");
  ASSERT_TRUE(dist != nullptr && dist->is_sequence());
  EXPECT_EQ(dist->items.size(), 4U);
  const y::Node* t = camera->find("T");
  ASSERT_TRUE(t != nullptr && t->is_sequence());
  EXPECT_EQ(t->items.size(), 2U);
  EXPECT_EQ(t->items[1].location.line, 7);
  EXPECT_EQ(doc->find("missing"), nullptr);
}

TEST(YamlDocument, TypedGettersReadValuesAndDefaults) {
  auto doc = y::parse_string(kSensors, "sensors.yaml");
  ASSERT_TRUE(doc.ok());
  y::Diagnostics diag;
  y::MappingReader root(*doc, "", diag);
  y::MappingReader cam = root.required_mapping("camera");
  EXPECT_EQ(cam.required_int("width"), 320);
  EXPECT_DOUBLE_EQ(cam.required_double("fx"), 280.5);
  EXPECT_DOUBLE_EQ(cam.optional_double("fy", 7.0), 7.0);
  auto d = cam.required_doubles("distortion", 4);
  ASSERT_EQ(d.size(), 4U);
  EXPECT_DOUBLE_EQ(d[1], -0.2);
  EXPECT_DOUBLE_EQ(d[3], 1e-3);
  auto tv = cam.required_doubles("T", 0);
  ASSERT_EQ(tv.size(), 2U);
  EXPECT_DOUBLE_EQ(tv[1], 2.0);
  EXPECT_EQ(cam.required_string("name"), "cam0");
  EXPECT_TRUE(cam.optional_bool("flag", false));
  EXPECT_EQ(cam.optional_int("missing", 9), 9);
  y::MappingReader gyro = root.optional_mapping("gyro");
  EXPECT_DOUBLE_EQ(gyro.optional_double("noise_density", 0.5), 0.5);
  EXPECT_TRUE(diag.ok()) << diag.error_text();
  EXPECT_TRUE(diag.warnings.empty());
}

TEST(YamlDocument, WrongTypeNamesFileLineAndKey) {
  auto doc = y::parse_string("camera:\n  width: 320\n\n\n\n\n  fx: abc\n", "sensors.yaml");
  ASSERT_TRUE(doc.ok());
  y::Diagnostics diag;
  y::MappingReader root(*doc, "", diag);
  y::MappingReader cam = root.required_mapping("camera");
  EXPECT_DOUBLE_EQ(cam.required_double("fx"), 0.0);
  ASSERT_EQ(diag.errors.size(), 1U);
  EXPECT_EQ(diag.errors[0], "sensors.yaml:7: camera.fx: expected a number, got \"abc\"");
}

TEST(YamlDocument, QuotedNumberIsNotANumber) {
  auto doc = y::parse_string("a: \"1.5\"\n", "f.yaml");
  ASSERT_TRUE(doc.ok());
  auto v = y::as_double(*doc->find("a"), "a");
  EXPECT_FALSE(v.ok());
}

TEST(YamlDocument, RejectsNonFiniteAndTrailingGarbage) {
  for (const char* text : {"a: .nan\n", "a: .inf\n", "a: 1.0x\n", "a: 1e999\n", "a: [1]\n"}) {
    auto doc = y::parse_string(text, "f.yaml");
    ASSERT_TRUE(doc.ok()) << text;
    EXPECT_FALSE(y::as_double(*doc->find("a"), "a").ok()) << text;
  }
  auto doc = y::parse_string("a: +2.5\nb: -3\nc: 2.5\nd: 99999999999999999999\n", "f.yaml");
  ASSERT_TRUE(doc.ok());
  EXPECT_DOUBLE_EQ(*y::as_double(*doc->find("a"), "a"), 2.5);
  EXPECT_EQ(*y::as_int(*doc->find("b"), "b"), -3);
  EXPECT_FALSE(y::as_int(*doc->find("c"), "c").ok());
  EXPECT_FALSE(y::as_int(*doc->find("d"), "d").ok());
}

TEST(YamlDocument, MissingRequiredKeyIsAnError) {
  auto doc = y::parse_string("camera:\n  width: 320\n", "sensors.yaml");
  ASSERT_TRUE(doc.ok());
  y::Diagnostics diag;
  y::MappingReader root(*doc, "", diag);
  y::MappingReader cam = root.required_mapping("camera");
  cam.required_double("fx");
  root.required_mapping("wheels").required_double("wheel_base");
  ASSERT_EQ(diag.errors.size(), 3U) << diag.error_text();
  EXPECT_NE(diag.errors[0].find("sensors.yaml:2: camera.fx: missing required key"),
            std::string::npos)
      << diag.errors[0];
  EXPECT_NE(diag.errors[1].find("wheels: missing required key"), std::string::npos);
  EXPECT_NE(diag.errors[2].find("wheels.wheel_base: missing required key"), std::string::npos);
}

TEST(YamlDocument, UnknownKeysAreWarnings) {
  auto doc = y::parse_string(kSensors, "sensors.yaml");
  ASSERT_TRUE(doc.ok());
  y::Diagnostics diag;
  y::MappingReader root(*doc, "", diag);
  y::MappingReader wheels = root.required_mapping("wheels");
  wheels.required_double("wheel_base");
  wheels.report_unknown_keys();
  root.report_unknown_keys();
  EXPECT_TRUE(diag.ok());
  ASSERT_EQ(diag.warnings.size(), 2U);
  EXPECT_EQ(diag.warnings[0], "sensors.yaml:12: wheels.extra: unknown key, ignored");
  EXPECT_EQ(diag.warnings[1], "sensors.yaml:1: camera: unknown key, ignored");
}

TEST(YamlDocument, WrongSequenceLengthAndBadItem) {
  auto doc = y::parse_string("d: [1, 2, 3]\ne: [1, x]\n", "f.yaml");
  ASSERT_TRUE(doc.ok());
  y::Diagnostics diag;
  y::MappingReader root(*doc, "", diag);
  root.required_doubles("d", 4);
  root.required_doubles("e", 2);
  ASSERT_EQ(diag.errors.size(), 2U);
  EXPECT_EQ(diag.errors[0], "f.yaml:1: d: expected 4 numbers, got 3");
  EXPECT_EQ(diag.errors[1], "f.yaml:2: e[1]: expected a number, got \"x\"");
}

TEST(YamlDocument, SyntaxErrorsAndUnsupportedFeaturesAreReported) {
  auto bad = y::parse_string("a: [1, 2\nb: 3\n", "f.yaml");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().rfind("f.yaml:", 0), 0U) << bad.error();
  auto dup = y::parse_string("a: 1\na: 2\n", "f.yaml");
  ASSERT_FALSE(dup.ok());
  EXPECT_EQ(dup.error(), "f.yaml:2: a: duplicate key");
  auto alias = y::parse_string("a: &x 1\nb: *x\n", "f.yaml");
  EXPECT_FALSE(alias.ok());
  auto tab = y::parse_string("a:\n\t- 1\n", "f.yaml");
  EXPECT_FALSE(tab.ok());
}

TEST(YamlDocument, NotAMappingIsAnError) {
  auto doc = y::parse_string("camera: 3\n", "f.yaml");
  ASSERT_TRUE(doc.ok());
  y::Diagnostics diag;
  y::MappingReader root(*doc, "", diag);
  y::MappingReader cam = root.required_mapping("camera");
  EXPECT_DOUBLE_EQ(cam.optional_double("fx", 1.0), 1.0);
  ASSERT_EQ(diag.errors.size(), 1U);
  EXPECT_EQ(diag.errors[0], "f.yaml:1: camera: expected a mapping, got \"3\"");
}

TEST(YamlDocument, EmptyDocumentIsNull) {
  auto doc = y::parse_string("", "f.yaml");
  ASSERT_TRUE(doc.ok());
  EXPECT_TRUE(doc->is_null());
  auto comment = y::parse_string("# only a comment\n", "f.yaml");
  ASSERT_TRUE(comment.ok());
  EXPECT_TRUE(comment->is_null());
}

TEST(YamlDocument, ParseFileNamesThePath) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("cleanslam_test_yaml_doc_" + std::to_string(::getpid()) + ".yaml");
  {
    std::ofstream out(path);
    out << "x: 1.0\ny: oops\n";
  }
  auto doc = y::parse_file(path.string());
  ASSERT_TRUE(doc.ok()) << doc.error();
  auto v = y::as_double(*doc->find("y"), "y");
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.error(), path.string() + ":2: y: expected a number, got \"oops\"");
  std::filesystem::remove(path);
  auto missing = y::parse_file(path.string());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("cannot open"), std::string::npos);
}
