#include "tkgslam/dynamic/ProtobufWire.h"

namespace tkgslam::dynamic {

namespace {

// Reads a varint at `pos`, advancing it; false if truncated or longer than 10 bytes.
bool readVarint(std::string_view in, size_t& pos, std::uint64_t& value) {
  value = 0;
  for (int shift = 0; shift < 70; shift += 7) {
    if (pos >= in.size()) return false;
    const auto byte = static_cast<unsigned char>(in[pos++]);
    if (shift == 63 && byte > 1) return false;  // the 10th byte holds the 64th bit only
    value |= std::uint64_t(byte & 0x7f) << shift;
    if (!(byte & 0x80)) return true;
  }
  return false;
}

}  // namespace

bool splitWireFields(std::string_view message, std::vector<WireField>& fields) {
  fields.clear();
  size_t pos = 0;
  while (pos < message.size()) {
    const size_t start = pos;
    std::uint64_t key = 0;
    if (!readVarint(message, pos, key)) return false;
    WireField field;
    const std::uint64_t number = key >> 3;
    if (number == 0 || number > 0x1fffffff) return false;  // protobuf's field-number range
    field.number = static_cast<std::uint32_t>(number);
    switch (key & 7) {
      case WireField::kVarint:
        field.type = WireField::kVarint;
        if (!readVarint(message, pos, field.varint)) return false;
        break;
      case WireField::kFixed64:
      case WireField::kFixed32: {
        field.type = static_cast<WireField::Type>(key & 7);
        const size_t size = field.type == WireField::kFixed64 ? 8 : 4;
        if (message.size() - pos < size) return false;
        pos += size;
        break;
      }
      case WireField::kLengthDelimited: {
        field.type = WireField::kLengthDelimited;
        std::uint64_t length = 0;
        if (!readVarint(message, pos, length) || length > message.size() - pos) return false;
        field.payload = message.substr(pos, size_t(length));
        pos += size_t(length);
        break;
      }
      default:
        return false;
    }
    field.encoded = message.substr(start, pos - start);
    fields.push_back(field);
  }
  return true;
}

void appendVarint(std::string& out, std::uint64_t value) {
  while (value >= 0x80) {
    out.push_back(static_cast<char>((value & 0x7f) | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<char>(value));
}

void appendLengthDelimited(std::string& out, std::uint32_t number, std::string_view payload) {
  appendVarint(out, (std::uint64_t(number) << 3) | WireField::kLengthDelimited);
  appendVarint(out, payload.size());
  out.append(payload);
}

}  // namespace tkgslam::dynamic
