#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tkgslam/dynamic/ProtobufWire.h"

namespace tkgslam {
namespace {

using dynamic::WireField;

TEST(ProtobufWire, SplitsEveryWireTypeAndWritesLengthDelimitedFieldsBack) {
  std::string message;
  dynamic::appendVarint(message, (1 << 3) | 0);  // field 1, varint 300
  dynamic::appendVarint(message, 300);
  message += std::string("\x15\x01\x02\x03\x04", 5);                  // field 2, fixed32
  message += std::string("\x19\x01\x02\x03\x04\x05\x06\x07\x08", 9);  // field 3, fixed64
  dynamic::appendLengthDelimited(message, 4, "abc");
  dynamic::appendLengthDelimited(message, 123456, std::string(200, 'x'));  // a two-byte length
  dynamic::appendVarint(message, (5 << 3) | 0);
  dynamic::appendVarint(message, ~0ull);  // ten bytes

  std::vector<WireField> fields;
  ASSERT_TRUE(dynamic::splitWireFields(message, fields));
  ASSERT_EQ(fields.size(), 6u);
  EXPECT_EQ(fields[0].number, 1u);
  EXPECT_EQ(fields[0].type, WireField::kVarint);
  EXPECT_EQ(fields[0].varint, 300u);
  EXPECT_EQ(fields[0].encoded, std::string("\x08\xac\x02"));  // the encoding of the protobuf docs
  EXPECT_EQ(fields[1].type, WireField::kFixed32);
  EXPECT_EQ(fields[1].encoded.size(), 5u);
  EXPECT_EQ(fields[2].type, WireField::kFixed64);
  EXPECT_EQ(fields[2].encoded.size(), 9u);
  EXPECT_EQ(fields[3].number, 4u);
  EXPECT_EQ(fields[3].payload, "abc");
  EXPECT_EQ(fields[4].number, 123456u);
  EXPECT_EQ(fields[4].payload, std::string(200, 'x'));
  EXPECT_EQ(fields[5].varint, ~0ull);
  std::string joined;
  for (const WireField& f : fields) joined += f.encoded;
  EXPECT_EQ(joined, message);  // the fields cover the message, in order
}

TEST(ProtobufWire, RefusesMalformedMessages) {
  std::vector<WireField> fields;
  EXPECT_TRUE(dynamic::splitWireFields("", fields));
  EXPECT_TRUE(fields.empty());
  const std::vector<std::string> bad{
      std::string("\x08", 1),                      // key without its value
      std::string("\x08\x80", 2),                  // varint cut short
      std::string("\x12\x05" "abc", 5),            // length past the end
      std::string("\x00\x01", 2),                  // field number 0
      std::string("\x0b\x0c", 2),                  // a group (wire type 3)
      std::string("\x0e\x00", 2),                  // wire type 6
      std::string("\x15\x01\x02", 3),              // fixed32 cut short
      std::string("\x08\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\x01", 12),  // an 11-byte varint
      std::string("\x08\xff\xff\xff\xff\xff\xff\xff\xff\xff\x02", 11),  // 10 bytes, but past 64 bits
      std::string("\x12\xff\xff\xff\xff\xff\xff\xff\xff\x7f", 10),      // a length of ~2^63
  };
  for (const std::string& message : bad) {
    EXPECT_FALSE(dynamic::splitWireFields(message, fields)) << testing::PrintToString(message);
  }
}

}  // namespace
}  // namespace tkgslam
