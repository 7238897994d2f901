// The map server's Range header (RFC 9110, 14.2): one range answered in part, a range past the end refused
// (416), anything else the whole file.
#include "server/api/byte_range.hpp"

#include <gtest/gtest.h>

namespace strata::api {
namespace {

using Kind = ByteRange::Kind;

TEST(ByteRange, OneRangeIsAPartClampedToTheFile) {
  ByteRange range = parse_byte_range("bytes=8-107", 1000);
  EXPECT_EQ(range.kind, Kind::kPart);
  EXPECT_EQ(range.first, 8U);
  EXPECT_EQ(range.last, 107U);
  range = parse_byte_range("bytes=900-", 1000);
  EXPECT_EQ(range.kind, Kind::kPart);
  EXPECT_EQ(range.last, 999U);
  range = parse_byte_range("bytes=990-5000", 1000);
  EXPECT_EQ(range.last, 999U);
  range = parse_byte_range("bytes=-16", 1000);  // the last 16 bytes
  EXPECT_EQ(range.kind, Kind::kPart);
  EXPECT_EQ(range.first, 984U);
  EXPECT_EQ(range.last, 999U);
  range = parse_byte_range("bytes=-5000", 1000);  // more than there is: all of it
  EXPECT_EQ(range.first, 0U);
}

TEST(ByteRange, NothingOfTheFileIsUnsatisfiable) {
  EXPECT_EQ(parse_byte_range("bytes=1000-", 1000).kind, Kind::kUnsatisfiable);
  EXPECT_EQ(parse_byte_range("bytes=2000-3000", 1000).kind, Kind::kUnsatisfiable);
  EXPECT_EQ(parse_byte_range("bytes=-0", 1000).kind, Kind::kUnsatisfiable);
  EXPECT_EQ(parse_byte_range("bytes=0-", 0).kind, Kind::kUnsatisfiable);
}

TEST(ByteRange, WhatDoesNotParseOrAsksForSeveralIsTheWholeFile) {
  for (const char* header : {"", "items=0-5", "bytes=5-3", "bytes=a-b", "bytes=0-1,5-6", "bytes=", "bytes=-",
                             "bytes=99999999999999999999999-"})
    EXPECT_EQ(parse_byte_range(header, 1000).kind, Kind::kWhole) << header;
}

}  // namespace
}  // namespace strata::api
