#pragma once
// The command line of the benchmark programs (bench/*.cpp): --help, option values checked as they
// are read, and a main() that turns every error into one line on stderr and exit code 2 (the
// project's rule for bad input), never an abort; and the median the programs report of their
// rounds. Each program keeps its own parsing loop:
//
//   int run(int argc, char** argv) {
//       for (int i = 1; i < argc; ++i) {
//           const std::string a = argv[i];
//           if (a == "--spp") spp = bench::int_option(argc, argv, i, 1);
//           else bench::reject_argument(a);
//       }
//       ...
//   }
//   int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }

#include "core/text.h"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

// A bad command line; run_main prints it as "<program>: <message> (see --help)".
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The value that follows the option argv[i] (i is moved onto it); UsageError when there is none.
inline const char* option_value(int argc, char** argv, int& i) {
    if (i + 1 >= argc) throw UsageError(std::string(argv[i]) + " needs a value");
    return argv[++i];
}

// `text` as a whole number from minimum to maximum (core/text.h's parse_integer); UsageError
// naming `option` otherwise, where std::atoi would give 0.
inline long long parse_whole(const std::string& option, const char* text, long long minimum, long long maximum) {
    long long value = 0;
    if (!candela::parse_integer(text, value) || value < minimum || value > maximum)
        throw UsageError(option + " must be a whole number from " + std::to_string(minimum) + " to " + std::to_string(maximum) + " (got " +
                         text + ")");
    return value;
}

// The whole-number value of the option argv[i], at least `minimum` (option_value, parse_whole).
inline int int_option(int argc, char** argv, int& i, int minimum) {
    const std::string option = argv[i];
    return int(parse_whole(option, option_value(argc, argv, i), minimum, INT_MAX));
}

// The numbers of a list such as "0.32,0.16" (commas or spaces between them, core/text.h's
// split_list and parse_finite_float); UsageError naming `option` for an item that is not one.
inline std::vector<float> number_list(const std::string& option, const std::string& text) {
    std::vector<float> values;
    for (const std::string& item : candela::split_list(text)) {
        float v = 0.0f;
        if (!candela::parse_finite_float(item, v)) throw UsageError(option + " takes numbers separated by commas (got " + item + ")");
        values.push_back(v);
    }
    return values;
}

// True for an argument that names an option: it starts with '-' (a lone "-" does not).
inline bool is_option(const std::string& a) { return a.size() > 1 && a[0] == '-'; }

// For an argument the program's loop does not know: UsageError, "unknown option --x" for one that
// starts with '-', "unexpected argument x" for any other.
[[noreturn]] inline void reject_argument(const std::string& a) {
    throw UsageError((is_option(a) ? "unknown option " : "unexpected argument ") + a);
}

// What main() does: with --help or -h anywhere prints `usage` to stdout and returns 0 before
// anything runs; otherwise returns run(argc, argv), and for an exception that escapes it (a
// UsageError, a candela::SceneError whose what() names the file and line, any std::exception)
// prints "<program>: <what()>" to stderr and returns 2.
inline int run_main(int argc, char** argv, const char* usage, int (*run)(int, char**)) {
    for (int i = 1; i < argc; ++i)
        if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
            std::fputs(usage, stdout);
            return 0;
        }
    const char* slash = std::strrchr(argv[0], '/');
    const char* program = slash ? slash + 1 : argv[0];
    try {
        return run(argc, argv);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "%s: %s (see --help)\n", program, e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: %s\n", program, e.what());
    }
    return 2;
}

// The median of a round's figures (the mean of the middle two for an even count); 0 for none.
inline double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace bench
