// The bench's machine description, from /proc/cpuinfo-format text: brand, family and model (a
// VM's brand alone, "AMD EPYC", does not tell Zen 3 from Zen 4), and the processor count.
#include "mcpose/bench.h"

#include <sstream>

#include <gtest/gtest.h>

namespace mcpose::bench {
namespace {

TEST(MachineDescription, BrandFamilyModelAndProcessors) {
  std::istringstream in(
      "processor\t: 0\nvendor_id\t: AuthenticAMD\ncpu family\t: 25\nmodel\t\t: 1\n"
      "model name\t: AMD EPYC\nstepping\t: 1\n\n"
      "processor\t: 1\nvendor_id\t: AuthenticAMD\ncpu family\t: 25\nmodel\t\t: 1\n"
      "model name\t: AMD EPYC\nstepping\t: 1\n");
  EXPECT_EQ(MachineDescriptionFrom(in, 8), "AMD EPYC (family 25 model 1), 2 logical CPUs");
}

TEST(MachineDescription, WithoutFamilyOrProcessorsFallsBack) {
  std::istringstream brand_only("model name\t: Some CPU\n");
  EXPECT_EQ(MachineDescriptionFrom(brand_only, 4), "Some CPU, 4 logical CPUs");
  std::istringstream empty("");
  EXPECT_EQ(MachineDescriptionFrom(empty, 3), "unknown CPU, 3 logical CPUs");
  // A line that is only a key, with no value after the colon.
  std::istringstream bare("cpu family\t:\nmodel\t\t:\nmodel name\t:\nprocessor\t: 0\n");
  EXPECT_EQ(MachineDescriptionFrom(bare, 3), "unknown CPU, 1 logical CPUs");
}

TEST(MachineDescription, ThisMachineNamesItsProcessorCount) {
  EXPECT_NE(MachineDescription().find(" logical CPUs"), std::string::npos);
}

}  // namespace
}  // namespace mcpose::bench
