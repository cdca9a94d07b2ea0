// run_isolated: a reader in a child process. A crash, a hang, a runaway allocation or an
// exception in the reader becomes an error naming the file and what happened; a result comes
// back byte for byte; the calling process lives on.
#include "isolated_reader.h"
#include "errors.h"
#include <gtest/gtest.h>
#include <chrono>
#include <csignal>
#include <new>
#include <thread>
#include <vector>

namespace {

hb::vtk::ReaderLimits limits(double timeout_s = 20.0, std::size_t memory_mb = 1024) {
  hb::vtk::ReaderLimits l;
  l.timeout_s = timeout_s;
  l.memory_mb = memory_mb;
  return l;
}

std::string error_of(const std::function<std::string()>& read, const hb::vtk::ReaderLimits& l = limits()) {
  try {
    hb::vtk::run_isolated("/data/x.nrrd", "NRRD", l, read);
  } catch (const hb::InvalidInput& e) {
    return e.what();
  }
  return "no error";
}

TEST(IsolatedReaderTest, ResultComesBackByteForByte) {
  std::string big(3 << 20, '\0');
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = char(i * 7919 % 251);
  EXPECT_EQ(hb::vtk::run_isolated("f", "NRRD", limits(), [&] { return big; }), big);
}

TEST(IsolatedReaderTest, CrashIsAnErrorNamingFileReaderAndSignal) {
  const std::string e = error_of([]() -> std::string {
    std::raise(SIGSEGV);
    return "";
  });
  EXPECT_EQ(e, "/data/x.nrrd: the NRRD reader failed on this file (it crashed: segmentation fault); the file is damaged or not supported");
  EXPECT_NE(error_of([]() -> std::string { std::abort(); }).find("(it crashed: aborted)"), std::string::npos);
}

TEST(IsolatedReaderTest, HangIsStoppedAtTheTimeout) {
  const auto start = std::chrono::steady_clock::now();
  const std::string e = error_of(
      []() -> std::string {
        for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
      },
      limits(0.3));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NE(e.find("/data/x.nrrd: the NRRD reader failed on this file (it was still running after 0.3 s and was stopped)"),
            std::string::npos) << e;
  EXPECT_NE(e.find("HB_READER_TIMEOUT_S"), std::string::npos) << e;
  EXPECT_LT(seconds, 5.0);
}

TEST(IsolatedReaderTest, RunawayAllocationMeetsTheMemoryLimit) {
  const std::string e = error_of(
      []() -> std::string {
        std::vector<char> v(std::size_t(4) << 30, 1);  // 4 GB against a 64 MB allowance
        return std::string(1, v[12345]);
      },
      limits(20.0, 64));
  EXPECT_NE(e.find("/data/x.nrrd: the NRRD reader failed on this file (it ran out of memory: it asked for more than the 64 MB allowed)"),
            std::string::npos) << e;
}

TEST(IsolatedReaderTest, ExceptionsKeepTheirTypeAndMessage) {
  EXPECT_THROW(hb::vtk::run_isolated("f", "NRRD", limits(), []() -> std::string { throw hb::IoError("f: gone"); }), hb::IoError);
  EXPECT_EQ(error_of([]() -> std::string { throw hb::InvalidInput("/data/x.nrrd: sizes missing"); }), "/data/x.nrrd: sizes missing");
  // A library's bare exception gets the file, the reader and a cause in the file's terms (not
  // the library's function name).
  EXPECT_EQ(error_of([]() -> std::string { throw std::length_error("vector::_M_default_append"); }),
            "/data/x.nrrd: the NRRD reader failed on this file (a count or size in the file asked it for an array longer than any memory "
            "holds); the file is damaged or not supported");
}

TEST(IsolatedReaderTest, ErrorsAreEscapedAndCutToAReadableLength) {
  // A reader's error quoting 64 KB of raw bytes (a NRRD data file LIST read from the voxels).
  const std::string e = error_of([]() -> std::string {
    throw hb::InvalidInput("/data/x.nrrd: the data file " + std::string(65536, '\x01') + " is missing");
  });
  EXPECT_LE(e.size(), 2100u);
  EXPECT_EQ(e.rfind("/data/x.nrrd: the data file \\x01\\x01", 0), 0u) << e.substr(0, 100);
  EXPECT_NE(e.find("(" + std::to_string(28 + 65536 + 11) + " bytes in all)"), std::string::npos) << e.substr(e.size() - 100);
  for (char c : e) EXPECT_TRUE(c >= 0x20 && c < 0x7F) << int((unsigned char)c);
}

TEST(IsolatedReaderTest, WithoutIsolationTheSameMessagesComeFromThisProcess) {
  hb::vtk::ReaderLimits l = limits();
  l.isolate = false;
  EXPECT_EQ(hb::vtk::run_isolated("f", "NRRD", l, [] { return std::string("ok"); }), "ok");
  EXPECT_EQ(error_of([]() -> std::string { throw std::bad_alloc(); }, l),
            "/data/x.nrrd: the NRRD reader failed on this file (it ran out of memory); the file is damaged, or needs more memory "
            "(HB_READER_MEMORY_MB)");
}

TEST(IsolatedReaderTest, EnvironmentSetsTheLimitsAndMalformedValuesAreRefused) {
  ::setenv("HB_READER_TIMEOUT_S", "12.5", 1);
  ::setenv("HB_READER_MEMORY_MB", "300", 1);
  hb::vtk::ReaderLimits l = hb::vtk::ReaderLimits::from_environment();
  EXPECT_EQ(l.timeout_s, 12.5);
  EXPECT_EQ(l.memory_mb, 300u);
  ::setenv("HB_READER_TIMEOUT_S", "soon", 1);
  EXPECT_THROW(hb::vtk::ReaderLimits::from_environment(), hb::InvalidInput);
  ::unsetenv("HB_READER_TIMEOUT_S");
  ::unsetenv("HB_READER_MEMORY_MB");
  l = hb::vtk::ReaderLimits::from_environment();
  EXPECT_EQ(l.timeout_s, 120.0);
  EXPECT_EQ(l.memory_mb, 8192u);
}

} // namespace
