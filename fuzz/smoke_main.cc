// A harness as an ordinary program, for the default (GCC) build and ctest: feeds every file of
// the corpus folder, then deterministic mutations of each (bit flips, boundary values, huge or
// negative numbers, truncation, cut or repeated chunks) to LLVMFuzzerTestOneInput. Not a fuzzer:
// it checks that every harness builds and that its seeds and their near neighbours are read
// without a crash or an exception other than varsfm::Error. A failing input is saved as
// smoke-failure-<harness> in the working folder, for the unit test that will hold it.
//
// Usage: <harness> CORPUS_DIR [MUTATIONS_PER_FILE (default 100)]
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "fuzz_support.h"

#if defined(__SANITIZE_ADDRESS__)
#define VARSFM_SMOKE_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VARSFM_SMOKE_SANITIZED 1
#endif
#endif
#ifdef VARSFM_SMOKE_SANITIZED
#include <sanitizer/common_interface_defs.h>
#endif

namespace {

namespace fs = std::filesystem;

// The input being run, saved by the failure handlers; fixed storage so the signal handler
// needs no allocation.
std::vector<uint8_t> g_input;
char g_failure_file[512];

void SaveInput() {
  const int fd = ::open(g_failure_file, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return;
  for (size_t done = 0; done < g_input.size();) {
    const ssize_t n = ::write(fd, g_input.data() + done, g_input.size() - done);
    if (n <= 0) break;
    done += static_cast<size_t>(n);
  }
  ::close(fd);
}

#ifndef VARSFM_SMOKE_SANITIZED
void OnSignal(int signal) {
  SaveInput();
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}
#endif

void OnTerminate() {
  SaveInput();
  std::fprintf(stderr, "uncaught exception");
  try {
    if (const auto e = std::current_exception()) std::rethrow_exception(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, ": %s", e.what());
  } catch (...) {
  }
  std::fprintf(stderr, "; input saved as %s\n", g_failure_file);
  std::abort();
}

// Text numbers that break parsers: overflow, negative counts, non-finite values.
const char* const kNumbers[] = {
    "-1",    "0",      "4294967296", "2147483648", "99999999999999999999",
    "1e308", "-1e308", "nan",        "inf",        "1e-320"};
// Binary values at the edges of 8-, 16-, 32- and 64-bit integers and of doubles.
const uint64_t kBoundaries[] = {0,
                                0xff,
                                0x7fff,
                                0xffff,
                                0x7fffffff,
                                0x80000000,
                                0xffffffff,
                                0x7fffffffffffffff,
                                ~0ull,
                                0x7ff0000000000000 /* inf */,
                                0x7ff8000000000000 /* nan */};

// One deterministic mutation of `in` drawn from `rng` (its raw output only, so every standard
// library gives the same sequence).
std::vector<uint8_t> Mutate(std::vector<uint8_t> in, std::mt19937& rng) {
  auto pick = [&](size_t n) { return n == 0 ? size_t{0} : static_cast<size_t>(rng() % n); };
  const int steps = 1 + static_cast<int>(pick(3));
  for (int step = 0; step < steps; ++step) {
    const size_t at = pick(in.size() + 1);
    switch (pick(7)) {
      case 0:
        if (!in.empty()) in[pick(in.size())] ^= static_cast<uint8_t>(1u << pick(8));
        break;
      case 1: {
        const uint8_t bytes[] = {0x00, 0xff, 0x7f, 0x80, '0', '9', '-', ' ', '\n', '/'};
        if (!in.empty()) in[pick(in.size())] = bytes[pick(std::size(bytes))];
        break;
      }
      case 2:
        in.resize(at);
        break;
      case 3: {
        const uint64_t value = kBoundaries[pick(std::size(kBoundaries))];
        const size_t width = size_t{1} << pick(4);  // 1, 2, 4 or 8 bytes
        for (size_t k = 0; k < width && at + k < in.size(); ++k)
          in[at + k] = static_cast<uint8_t>(value >> (8 * k));
        break;
      }
      case 4: {
        const std::string number = kNumbers[pick(std::size(kNumbers))];
        in.insert(in.begin() + static_cast<std::ptrdiff_t>(at), number.begin(), number.end());
        break;
      }
      case 5: {
        const size_t length = std::min(pick(64) + 1, in.size() - at);
        in.insert(in.begin() + static_cast<std::ptrdiff_t>(at),
                  in.begin() + static_cast<std::ptrdiff_t>(at),
                  in.begin() + static_cast<std::ptrdiff_t>(at + length));
        break;
      }
      default: {
        const size_t length = std::min(pick(64) + 1, in.size() - at);
        in.erase(in.begin() + static_cast<std::ptrdiff_t>(at),
                 in.begin() + static_cast<std::ptrdiff_t>(at + length));
      }
    }
  }
  return in;
}

void Run(const std::vector<uint8_t>& input) {
  g_input = input;
  LLVMFuzzerTestOneInput(g_input.data(), g_input.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR [MUTATIONS_PER_FILE]\n", argv[0]);
    return 2;
  }
  const fs::path corpus = argv[1];
  const int mutations = argc > 2 ? std::atoi(argv[2]) : 100;
  const std::string name = fs::path(argv[0]).filename().string();
  std::snprintf(g_failure_file, sizeof(g_failure_file), "smoke-failure-%s", name.c_str());
  std::set_terminate(OnTerminate);
#ifdef VARSFM_SMOKE_SANITIZED
  // The sanitizers catch faults themselves and report them before dying.
  __sanitizer_set_death_callback(SaveInput);
#else
  for (int signal : {SIGSEGV, SIGABRT, SIGBUS, SIGFPE, SIGILL}) std::signal(signal, OnSignal);
#endif

  std::vector<fs::path> files;
  if (fs::is_directory(corpus))
    for (const auto& entry : fs::directory_iterator(corpus))
      if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    std::fprintf(stderr, "%s: no corpus files in %s\n", name.c_str(), corpus.c_str());
    return 1;
  }
  size_t runs = 0;
  for (size_t f = 0; f < files.size(); ++f) {
    std::ifstream in(files[f], std::ios::binary);
    const std::vector<uint8_t> seed((std::istreambuf_iterator<char>(in)),
                                    std::istreambuf_iterator<char>());
    Run(seed);
    std::mt19937 rng(static_cast<uint32_t>(f + 1));
    for (int m = 0; m < mutations; ++m) Run(Mutate(seed, rng));
    runs += 1 + static_cast<size_t>(mutations);
  }
  std::printf("%s: %zu inputs from %zu corpus files, no failure\n", name.c_str(), runs,
              files.size());
  return 0;
}
