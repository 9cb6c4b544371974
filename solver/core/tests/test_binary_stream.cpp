// The checkpoint's binary records (core/binary_stream.hpp): what the writer
// stores, the reader returns bit for bit; a record cut short, a section of
// another tag or a newer version, or an array longer than allowed is refused
// with a SolverError naming what was being read.
#include "core/binary_stream.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace fdem::checkpoint {
namespace {

std::string written(void (*write)(Writer&)) {
  std::ostringstream out(std::ios::out | std::ios::binary);
  Writer w(out);
  write(w);
  return out.str();
}

// The message of the SolverError `read` throws on `bytes` ("" when none).
template <class Read>
std::string refusal(const std::string& bytes, Read read) {
  std::istringstream in(bytes, std::ios::in | std::ios::binary);
  Reader r(in);
  try {
    read(r);
  } catch (const SolverError& e) {
    return e.what();
  }
  return "";
}

TEST(BinaryStream, EveryRecordReadsBackBitForBit) {
  const std::vector<double> values = {0.1, -0.0, std::numeric_limits<double>::denorm_min(), 1e308};
  const std::vector<Index> ids = {0, 7, -1, 1 << 30};
  std::ostringstream out(std::ios::out | std::ios::binary);
  Writer w(out);
  w.section("DEM", 2);
  w.u8(200);
  w.u32(0xdeadbeefU);
  w.u64(0x0123456789abcdefULL);
  w.i64(-42);
  w.f64(std::nextafter(1.0, 2.0));
  w.boolean(true);
  w.vec3(Vec3(1.5, -2.5, 1e-300));
  w.doubles(values);
  w.indices(ids);

  std::istringstream in(out.str(), std::ios::in | std::ios::binary);
  Reader r(in);
  EXPECT_EQ(r.section("DEM", 3), 2u);
  EXPECT_EQ(r.u8("u8"), 200u);
  EXPECT_EQ(r.u32("u32"), 0xdeadbeefU);
  EXPECT_EQ(r.u64("u64"), 0x0123456789abcdefULL);
  EXPECT_EQ(r.i64("i64"), -42);
  EXPECT_EQ(r.f64("f64"), std::nextafter(1.0, 2.0));
  EXPECT_TRUE(r.boolean("flag"));
  EXPECT_EQ(r.vec3("vec3"), Vec3(1.5, -2.5, 1e-300));
  const std::vector<double> back = r.doubles("values", values.size());
  ASSERT_EQ(back.size(), values.size());
  EXPECT_EQ(std::memcmp(back.data(), values.data(), values.size() * sizeof(double)), 0) << "-0.0 keeps its sign bit";
  EXPECT_EQ(r.indices("ids", ids.size()), ids);
  char extra = 0;
  EXPECT_FALSE(in.read(&extra, 1)) << "the reader took exactly what the writer wrote";
}

TEST(BinaryStream, SectionTagIsPaddedToFourCharacters) {
  EXPECT_EQ(written([](Writer& w) { w.section("SIM", 1); }).substr(0, 4), "SIM ");
}

TEST(BinaryStream, RecordCutShortIsRefusedNamingWhatWasRead) {
  const std::string bytes = written([](Writer& w) { w.f64(1.0); });
  const std::string what = refusal(bytes.substr(0, 5), [](Reader& r) { (void)r.f64("the time"); });
  EXPECT_NE(what.find("truncated"), std::string::npos) << what;
  EXPECT_NE(what.find("the time"), std::string::npos) << what;
}

TEST(BinaryStream, SectionOfAnotherTagOrANewerVersionIsRefused) {
  const std::string bytes = written([](Writer& w) { w.section("FLUI", 3); });
  const std::string other = refusal(bytes, [](Reader& r) { (void)r.section("DEM", 3); });
  EXPECT_NE(other.find("expected section 'DEM '"), std::string::npos) << other;
  const std::string newer = refusal(bytes, [](Reader& r) { (void)r.section("FLUI", 2); });
  EXPECT_NE(newer.find("version 3"), std::string::npos) << newer;
  EXPECT_EQ(refusal(bytes, [](Reader& r) { (void)r.section("FLUI", 3); }), "");
}

TEST(BinaryStream, ArrayLongerThanAllowedOrOfAnotherLengthIsRefused) {
  const std::string bytes = written([](Writer& w) { w.doubles(std::vector<double>(5, 1.0)); });
  EXPECT_NE(refusal(bytes, [](Reader& r) { (void)r.doubles("porosity", 4); }).find("at most 4"), std::string::npos);
  EXPECT_NE(refusal(bytes, [](Reader& r) { (void)r.doubles_exactly("porosity", 6); }).find("this run has 6"),
            std::string::npos);
  // A corrupt length far beyond the data fails at the end of the data, not in the allocator.
  const std::string huge = written([](Writer& w) { w.u64(std::uint64_t{1} << 40); });
  EXPECT_NE(refusal(huge, [](Reader& r) { (void)r.doubles("positions", std::size_t{1} << 41); }).find("truncated"),
            std::string::npos);
}

TEST(BinaryStream, FlagOtherThanZeroOrOneIsRefused) {
  const std::string bytes = written([](Writer& w) { w.u8(2); });
  EXPECT_NE(refusal(bytes, [](Reader& r) { (void)r.boolean("fluid present"); }).find("not a flag"), std::string::npos);
}

}  // namespace
}  // namespace fdem::checkpoint
