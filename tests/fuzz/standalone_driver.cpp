// Runs a fuzz target (LLVMFuzzerTestOneInput) without libFuzzer, for the compilers and builds
// that have none (GCC, the sanitizer build): every seed of the corpus given, then --runs inputs
// mutated from the seeds by a fixed-seed generator (bit flips, bytes replaced, inserted, deleted
// or duplicated, truncation, splices of two seeds, digits and signs swapped for the parsers).
// A crash, an abort or a sanitizer report fails the run; the host-fuzz preset builds the same
// targets against libFuzzer for longer, coverage-guided runs (tools/fuzz.sh).
//
//   fuzz_TARGET [--runs N] [--seed S] [--max-len L] CORPUS_DIR_OR_FILE...
//
// The input that fails is written to crash-input.bin in the working folder; run the target on that
// file alone to reproduce it.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
// Present in sanitizer builds: called before a sanitizer ends the process.
extern "C" void __sanitizer_set_death_callback(void (*callback)()) __attribute__((weak));

namespace {

using Bytes = std::vector<std::uint8_t>;

class SplitMix {
 public:
  explicit SplitMix(std::uint64_t seed) : s_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31U);
  }
  std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(next() % n); }

 private:
  std::uint64_t s_;
};

bool read_file(const std::filesystem::path& p, Bytes& out) {
  std::FILE* f = std::fopen(p.c_str(), "rb");
  if (f == nullptr) {
    return false;
  }
  out.clear();
  std::uint8_t buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof(buffer), f)) > 0) {
    out.insert(out.end(), buffer, buffer + n);
  }
  const bool ok = std::ferror(f) == 0;
  std::fclose(f);
  return ok;
}

void mutate(Bytes& b, const std::vector<Bytes>& seeds, SplitMix& rng, std::size_t max_len) {
  static constexpr char kTokens[] = "0123456789-+.eE,:\n #\"'[]{}nNaIif";
  const std::size_t edits = 1 + rng.below(4);
  for (std::size_t e = 0; e < edits; ++e) {
    const std::size_t pos = rng.below(b.size() + 1);
    switch (rng.below(8)) {
      case 0:
        if (!b.empty()) {
          b[std::min(pos, b.size() - 1)] ^= static_cast<std::uint8_t>(1U << rng.below(8));
        }
        break;
      case 1:
        if (!b.empty()) {
          b[std::min(pos, b.size() - 1)] = static_cast<std::uint8_t>(rng.next());
        }
        break;
      case 2:
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(pos),
                 static_cast<std::uint8_t>(rng.next()));
        break;
      case 3:
        if (pos < b.size()) {
          const std::size_t n = std::min(b.size() - pos, 1 + rng.below(16));
          b.erase(b.begin() + static_cast<std::ptrdiff_t>(pos),
                  b.begin() + static_cast<std::ptrdiff_t>(pos + n));
        }
        break;
      case 4:
        if (pos < b.size()) {
          const std::size_t n = std::min(b.size() - pos, 1 + rng.below(32));
          const Bytes chunk(b.begin() + static_cast<std::ptrdiff_t>(pos),
                            b.begin() + static_cast<std::ptrdiff_t>(pos + n));
          const std::size_t at = rng.below(b.size() + 1);
          b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), chunk.begin(), chunk.end());
        }
        break;
      case 5:
        b.resize(rng.below(b.size() + 1));
        break;
      case 6: {
        const Bytes& other = seeds[rng.below(seeds.size())];
        const std::size_t from = rng.below(other.size() + 1);
        b.resize(std::min(pos, b.size()));
        b.insert(b.end(), other.begin() + static_cast<std::ptrdiff_t>(from), other.end());
        break;
      }
      default:
        if (!b.empty()) {
          b[std::min(pos, b.size() - 1)] =
              static_cast<std::uint8_t>(kTokens[rng.below(sizeof(kTokens) - 1)]);
        }
        break;
    }
  }
  if (b.size() > max_len) {
    b.resize(max_len);
  }
}

const std::uint8_t* g_current = nullptr;
std::size_t g_current_size = 0;

void save_current_input() {
  const int fd = ::open("crash-input.bin", O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    std::size_t done = 0;
    while (done < g_current_size) {
      const ssize_t n = ::write(fd, g_current + done, g_current_size - done);
      if (n <= 0) {
        break;
      }
      done += static_cast<std::size_t>(n);
    }
    ::close(fd);
  }
  static constexpr char kNote[] = "fuzz: the failing input is in crash-input.bin\n";
  [[maybe_unused]] const ssize_t n = ::write(2, kNote, sizeof(kNote) - 1);
}

extern "C" void on_fatal_signal(int sig) {
  save_current_input();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void run_one(const Bytes& b) {
  g_current = b.data();
  g_current_size = b.size();
  LLVMFuzzerTestOneInput(b.data(), b.size());
}

int usage() {
  std::fprintf(stderr,
               "usage: fuzz_TARGET [--runs N] [--seed S] [--max-len L] CORPUS_DIR_OR_FILE...\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t runs = 0;
  std::uint64_t seed = 1;
  std::size_t max_len = 1U << 16U;
  std::vector<std::filesystem::path> inputs;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--runs" || a == "--seed" || a == "--max-len") && i + 1 < argc) {
      const std::uint64_t v = std::strtoull(argv[++i], nullptr, 10);
      if (a == "--runs") {
        runs = v;
      } else if (a == "--seed") {
        seed = v;
      } else {
        max_len = static_cast<std::size_t>(v);
      }
    } else if (!a.empty() && a[0] == '-') {
      return usage();
    } else {
      inputs.emplace_back(a);
    }
  }
  std::vector<std::filesystem::path> files;
  for (const auto& p : inputs) {
    std::error_code ec;
    if (std::filesystem::is_directory(p, ec)) {
      for (const auto& e : std::filesystem::directory_iterator(p)) {
        if (e.is_regular_file()) {
          files.push_back(e.path());
        }
      }
    } else if (std::filesystem::is_regular_file(p, ec)) {
      files.push_back(p);
    } else {
      std::fprintf(stderr, "fuzz: %s: no such file or folder\n", p.c_str());
      return 2;
    }
  }
  std::sort(files.begin(), files.end());
  for (const int sig : {SIGABRT, SIGSEGV, SIGFPE, SIGILL, SIGBUS}) {
    std::signal(sig, on_fatal_signal);
  }
  if (&__sanitizer_set_death_callback != nullptr) {
    __sanitizer_set_death_callback(save_current_input);
  }
  std::vector<Bytes> seeds;
  for (const auto& f : files) {
    Bytes b;
    if (!read_file(f, b)) {
      std::fprintf(stderr, "fuzz: %s: cannot read\n", f.c_str());
      return 2;
    }
    run_one(b);
    seeds.push_back(std::move(b));
  }
  if (seeds.empty()) {
    seeds.emplace_back();
  }
  SplitMix rng(seed);
  for (std::uint64_t r = 0; r < runs; ++r) {
    Bytes b = seeds[rng.below(seeds.size())];
    mutate(b, seeds, rng, max_len);
    run_one(b);
    if (runs >= 10 && (r + 1) % (runs / 10) == 0) {
      std::fprintf(stderr, "fuzz: %llu of %llu mutated inputs\n",
                   static_cast<unsigned long long>(r + 1), static_cast<unsigned long long>(runs));
    }
  }
  std::printf("fuzz: %zu seeds and %llu mutated inputs run, none failed\n", files.size(),
              static_cast<unsigned long long>(runs));
  return 0;
}
