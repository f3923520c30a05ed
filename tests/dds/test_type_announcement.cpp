// Which types announce their TypeObject in discovery. Debian's Fast DDS 2.9.1 discovery server crashes on the
// TypeObject of a type holding a sequence of structs (idl/name_only_types.cmake), so those types' generated type
// supports announce none; every other type keeps it (generic tools decode it: integration_type_information).
// The IDL is read here, so a new type with a sequence of structs fails until it is sent by name only too.
#include "causal_twinPubSubTypes.h"

#include <gtest/gtest.h>

#include <fstream>
#include <initializer_list>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace {

// Struct name -> the names its sequence members hold ("sequence<T" or "sequence<T, N>").
std::map<std::string, std::set<std::string>> sequence_elements(const std::string& idl_text) {
  std::map<std::string, std::set<std::string>> out;
  const std::regex head(R"(^\s*struct\s+(\w+)\s*\{)");
  const std::regex element(R"(sequence\s*<\s*([\w:]+))");
  std::istringstream in(idl_text);
  std::string line;
  std::string current;
  while (std::getline(in, line)) {
    const std::string code = line.substr(0, line.find("//"));
    std::smatch m;
    if (std::regex_search(code, m, head)) {
      current = m[1];
      out[current];
    } else if (code.find("};") != std::string::npos) {
      current.clear();
    } else if (!current.empty() && std::regex_search(code, m, element)) {
      out[current].insert(m[1]);
    }
  }
  return out;
}

TEST(TypeAnnouncement, TheTypesHoldingASequenceOfStructsAreTheNameOnlyOnes) {
  std::ifstream file(CAUSAL_TWIN_IDL_FILE);
  ASSERT_TRUE(file) << CAUSAL_TWIN_IDL_FILE;
  std::stringstream text;
  text << file.rdbuf();
  const auto structs = sequence_elements(text.str());
  ASSERT_GT(structs.count("VibrationFrame"), 0u) << "the IDL reader found no structs";
  std::set<std::string> holding;
  for (const auto& [name, elements] : structs) {
    for (const auto& element : elements) {
      if (structs.count(element) > 0) holding.insert(name);
    }
  }
  EXPECT_EQ(holding, (std::set<std::string>{"CausalFactorBatch", "CausalFactorSet"}))
      << "a type holding a sequence of structs must be sent by name only: add it to idl/name_only_types.cmake "
         "and here";
}

TEST(TypeAnnouncement, NameOnlyTypesAnnounceNoTypeObjectTheOthersDo) {
  causal_twin::CausalFactorBatchPubSubType batch;
  causal_twin::CausalFactorSetPubSubType set;
  for (const eprosima::fastdds::dds::TopicDataType* type :
       std::initializer_list<const eprosima::fastdds::dds::TopicDataType*>{&batch, &set}) {
    EXPECT_FALSE(type->auto_fill_type_object()) << type->getName();
    EXPECT_FALSE(type->auto_fill_type_information()) << type->getName();
  }
  causal_twin::VibrationFramePubSubType frame;
  causal_twin::AlarmPubSubType alarm;
  EXPECT_TRUE(frame.auto_fill_type_object());
  EXPECT_TRUE(frame.auto_fill_type_information());
  EXPECT_TRUE(alarm.auto_fill_type_object());
  EXPECT_TRUE(alarm.auto_fill_type_information());
}

}  // namespace
