// cleanslam-paper: the figures of Choi et al. (2012), Section 4, as CSV on stdout.
#include <charconv>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cleanslam/paper_models/multi_hypothesis_model.hpp"
#include "figures.hpp"
#include "plot.hpp"
#include "table.hpp"

namespace {

namespace paper = cleanslam::tools::paper;

constexpr int kUsageError = 2;

constexpr const char* kUsage =
    "usage: cleanslam-paper FIGURE [options] [--plot FILE.png]\n"
    "  fig10 --motion forward|lateral [--hypotheses N]   one-step error of the four models\n"
    "  fig8                                              RMS error over eps_ct x depth error\n"
    "  fig9 [--runs N] [--seed S]                        Monte Carlo RMS error over eps_ct\n"
    "  fig7                                              true and estimated landmarks, 1-sigma\n"
    "CSV goes to stdout (units: cm); --plot also writes FILE.png (and FILE.png.csv) with\n"
    "plot_paper.py, run by $CLEANSLAM_PYTHON (default /usr/bin/python3) with matplotlib.\n";

int usage_error(const std::string& message) {
  std::cerr << "cleanslam-paper: " << message << "\n" << kUsage;
  return kUsageError;
}

template <typename T>
std::optional<T> parse_number(std::string_view text, T min, T max) {
  T value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc{} || end != text.data() + text.size() || value < min || value > max) {
    return std::nullopt;
  }
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  if (args.empty()) {
    return usage_error("missing FIGURE");
  }
  if (args[0] == "-h" || args[0] == "--help") {
    std::cout << kUsage;
    return 0;
  }
  const std::string figure(args[0]);
  if (figure != "fig7" && figure != "fig8" && figure != "fig9" && figure != "fig10") {
    return usage_error("unknown figure '" + figure + "'");
  }
  paper::Fig10Options fig10;
  paper::Fig9Options fig9;
  bool motion_given = false;
  std::string plot_file;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string option(args[i]);
    const auto value = [&]() -> std::optional<std::string_view> {
      if (i + 1 >= args.size()) {
        return std::nullopt;
      }
      return args[++i];
    };
    const auto allowed = [&](std::initializer_list<const char*> figures) {
      for (const char* f : figures) {
        if (figure == f) {
          return true;
        }
      }
      return false;
    };
    if (option == "--plot") {
      const auto v = value();
      if (!v || v->empty()) {
        return usage_error("--plot needs a FILE.png");
      }
      plot_file = std::string(*v);
    } else if (option == "--motion" && allowed({"fig10"})) {
      const auto v = value();
      if (v && *v == "forward") {
        fig10.motion = cleanslam::paper_models::Motion::kForward;
      } else if (v && *v == "lateral") {
        fig10.motion = cleanslam::paper_models::Motion::kLateral;
      } else {
        return usage_error("--motion takes forward or lateral, got '" +
                           std::string(v.value_or("")) + "'");
      }
      motion_given = true;
    } else if (option == "--hypotheses" && allowed({"fig10"})) {
      const auto v = value();
      const auto n = v ? parse_number<std::size_t>(*v, 1, cleanslam::paper_models::kMaxHypotheses)
                       : std::nullopt;
      if (!n) {
        return usage_error("--hypotheses takes an integer in [1, " +
                           std::to_string(cleanslam::paper_models::kMaxHypotheses) + "], got '" +
                           std::string(v.value_or("")) + "'");
      }
      fig10.hypotheses = *n;
    } else if (option == "--runs" && allowed({"fig9"})) {
      const auto v = value();
      const auto n = v ? parse_number<int>(*v, 1, 100000) : std::nullopt;
      if (!n) {
        return usage_error("--runs takes an integer in [1, 100000], got '" +
                           std::string(v.value_or("")) + "'");
      }
      fig9.runs = *n;
    } else if (option == "--seed" && allowed({"fig9"})) {
      const auto v = value();
      const auto n = v ? parse_number<std::uint32_t>(*v, 0, 0xffffffffU) : std::nullopt;
      if (!n) {
        return usage_error("--seed takes an unsigned 32-bit integer, got '" +
                           std::string(v.value_or("")) + "'");
      }
      fig9.seed = *n;
    } else {
      return usage_error("unknown option '" + option + "' for " + figure);
    }
  }
  if (figure == "fig10" && !motion_given) {
    return usage_error("fig10 needs --motion forward|lateral");
  }

  paper::Table table;
  if (figure == "fig10") {
    table = paper::fig10(fig10);
  } else if (figure == "fig8") {
    table = paper::fig8();
  } else if (figure == "fig9") {
    table = paper::fig9(fig9);
  } else {
    table = paper::fig7();
  }
  paper::write_csv(std::cout, table);
  for (const auto& note : table.notes) {
    std::cerr << "cleanslam-paper: " << note << "\n";
  }
  if (plot_file.empty()) {
    return 0;
  }
  const std::string csv_file = plot_file + ".csv";
  {
    std::ofstream csv(csv_file);
    paper::write_csv(csv, table);
    if (!csv.flush()) {
      std::cerr << "cleanslam-paper: cannot write " << csv_file << "\n";
      return 1;
    }
  }
  const std::string script = paper::find_plot_script(argv[0]);
  if (script.empty()) {
    std::cerr << "cleanslam-paper: plot_paper.py not found (set CLEANSLAM_PLOT_SCRIPT, or install "
                 "it beside the executable or in ../share/cleanslam)\n";
    return 1;
  }
  std::string error;
  const int status = paper::run_plot_script(script, figure, csv_file, plot_file, error);
  if (status != 0) {
    std::cerr << "cleanslam-paper: plotting " << plot_file << " failed: " << error << "\n";
    return 1;
  }
  return 0;
}
