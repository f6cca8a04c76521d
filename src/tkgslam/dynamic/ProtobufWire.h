#pragma once
// The protocol-buffer wire format (https://protobuf.dev/programming-guides/encoding/), as much of it
// as rewriting an ONNX graph needs: a message split into its fields, and fields written back. No
// schema and no libprotobuf - the fields are read by number, and whatever is not changed is copied
// byte for byte.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace tkgslam::dynamic {

/// One field of a message as it is on the wire.
struct WireField {
  enum Type : std::uint8_t { kVarint = 0, kFixed64 = 1, kLengthDelimited = 2, kFixed32 = 5 };
  std::uint32_t number = 0;
  Type type = kVarint;
  std::uint64_t varint = 0;  ///< the value of a varint field
  std::string_view payload;  ///< the bytes of a length-delimited field (string, bytes, sub-message)
  std::string_view encoded;  ///< the whole field: key, length and value
};

/// Splits `message` into its fields, in order (views into `message`). False when it is not a
/// well-formed message: a truncated or over-long varint, a length past the end, field number 0,
/// a group (wire types 3 and 4, deprecated) or an unknown wire type.
bool splitWireFields(std::string_view message, std::vector<WireField>& fields);

/// Appends the varint encoding of `value`.
void appendVarint(std::string& out, std::uint64_t value);

/// Appends a length-delimited field: key, length, `payload`.
void appendLengthDelimited(std::string& out, std::uint32_t number, std::string_view payload);

}  // namespace tkgslam::dynamic
