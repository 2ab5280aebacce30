// One declarative option table per subcommand. Each option is declared once — its flags, the
// field it fills, its help text and its validation — and from that single declaration come the
// CLI11 registration, the `--help` line (with the default), the config-file key (the long flag
// without "--", '-' → '_') and the reading of that key from `--config FILE`. Values from the
// command line win over the file; the file wins over the field's initial value (the default).
//
// Every value, whether typed on the command line or read from the file, goes through the same
// parser and checks, and a bad one is reported as one line:
//   --flag: problem                (command line)
//   FILE:LINE: key: problem        (config file; an unknown key: FILE:LINE: unknown key 'k')
// thrown as OptionError / ConfigError while CLI11 parses; main() prints it and exits 1. Usage
// errors CLI11 itself finds (unknown flag, wrong number of values) keep their exit code 2.
//
// Use (e.g. detect, which still registers its options by hand; adopting this means):
//   CLI::App* cmd = app.add_subcommand("detect", "…");
//   auto options = std::make_shared<OptionTable>();
//   options->add("--input,-i", o.input, "Telemetry CSV, or - for standard input");
//   options->add("--stride", o.stride, "Evaluate every N samples …").range(1, 1000);
//   options->add("--quiet,-q", o.quiet, "No summary");            // a bool field is a flag
//   options->addConfigFile(o.config);   // optional: --config FILE with keys input, stride, quiet …
//   attachOptions(*cmd, options);                                   // resolves when parsed
// (detect's test expecting exit 2 for `--stride 0` then sees exit 1 with "--stride: …").
// `o` must outlive the parse (main() keeps the option structs for the whole run).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <initializer_list>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace quadfdi::cli {

// A bad value on the command line, worded for the user: "--flag: problem".
class OptionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Text → value for the supported field types; each returns "" or the problem ("needs an integer,
// got 'ten'"). Integers accept integral decimals such as 1e3, as config files always have.
std::string parseOptionValue(const std::string& text, std::string& value);
std::string parseOptionValue(const std::string& text, int& value);
std::string parseOptionValue(const std::string& text, unsigned long long& value);
std::string parseOptionValue(const std::string& text, double& value);
std::string parseOptionValue(const std::string& text, bool& value);  // true | false

// One declared option. Made by OptionTable::add; the setters return *this to chain.
class Option {
 public:
  // Values must be one of `allowed` (strings, or each element of a list of strings).
  Option& choices(std::vector<std::string> allowed);
  // Numbers (or each element of a list) must lie in [low, high].
  Option& range(double low, double high);
  Option& atLeast(double low);
  // Numbers must be > low (and <= high).
  Option& above(double low, double high = std::numeric_limits<double>::infinity());
  // Any further check of one value's text; returns "" or the problem.
  Option& check(std::function<std::string(const std::string& text)> problem_of);
  // A list takes exactly `n` values (the default for lists: one or more).
  Option& values(int n);
  // Must be given, on the command line or in the config file.
  Option& required();
  // What --help shows as the default instead of the field's initial value ("" shows none).
  Option& defaultText(std::string text);
  // A file the user may name by its path in the shipped tree ("configs/randomisation-default.toml",
  // "models/tcn-quad450.qfdw"): opened from the shipped data folder when it is not found as given
  // (cli/shipped_files.h: shippedFile), so that an installed quadfdi runs from any folder.
  Option& shippedFile();
  // A vehicle description: shippedFile, and a bare library name ("quad450") is the library's
  // description; a bare name that is neither is refused, naming the library's vehicles.
  Option& vehicleFile();
  // Plant parameters: a named set (nominal, perturbed, perturbed-strong) as it is; anything else
  // as vehicleFile, so --params takes a library vehicle by name as --vehicle does.
  Option& paramsFile();

  const std::string& key() const { return key_; }
  const std::string& longFlag() const { return long_flag_; }

 private:
  friend class OptionTable;

  std::string checkText(const std::string& text) const;  // choices and the custom check
  std::string checkNumber(double v) const;                // the range
  enum class FileKind { kNone, kShipped, kVehicle, kParams };
  // The text a file option's value is opened as, or its problem (shippedFile(), vehicleFile(), paramsFile()).
  std::string fileText(const std::string& given, std::string& problem) const;
  template <typename E>
  std::string parseOne(const std::string& given, E& out) const {
    std::string problem;
    const std::string text = file_kind_ == FileKind::kNone ? given : fileText(given, problem);
    if (!problem.empty()) return problem;
    if (std::string p = checkText(text); !p.empty()) return p;
    if (std::string p = parseOptionValue(text, out); !p.empty()) return p;
    if constexpr (std::is_arithmetic_v<E> && !std::is_same_v<E, bool>) return checkNumber(static_cast<double>(out));
    return {};
  }
  // Parses and checks `texts` (their count already checked) and, when `store`, sets `field`.
  template <typename E>
  std::string assign(E& field, const std::vector<std::string>& texts, bool store) const {
    E v{};
    if (std::string p = parseOne(texts.front(), v); !p.empty()) return p;
    if (store) field = v;
    return {};
  }
  template <typename E>
  std::string assign(std::optional<E>& field, const std::vector<std::string>& texts, bool store) const {
    E v{};
    if (std::string p = parseOne(texts.front(), v); !p.empty()) return p;
    if (store) field = v;
    return {};
  }
  template <typename E>
  std::string assign(std::vector<E>& field, const std::vector<std::string>& texts, bool store) const {
    std::vector<E> vs(texts.size());
    for (std::size_t i = 0; i < texts.size(); ++i)
      if (std::string p = parseOne(texts[i], vs[i]); !p.empty()) return p;
    if (store) field = std::move(vs);
    return {};
  }

  std::string flags_;      // CLI11 names, e.g. "--output,-o"
  std::string long_flag_;  // the first long name, e.g. "--output"
  std::string key_;        // config-file key, e.g. "output"
  std::string help_;
  std::string type_name_;  // INT, NUMBER, TEXT …; a choice list shows as "a|b"
  std::optional<std::string> default_text_;  // unset: none shown
  bool is_flag_ = false;   // bool field: present = true, no value on the command line
  bool is_list_ = false;
  int exact_count_ = 0;    // lists: 0 = one or more
  bool required_ = false;
  FileKind file_kind_ = FileKind::kNone;
  std::vector<std::string> choices_;
  double low_ = -std::numeric_limits<double>::infinity();
  double high_ = std::numeric_limits<double>::infinity();
  bool low_open_ = false;
  std::function<std::string(const std::string&)> check_;
  // Parses and checks the texts and, when asked, stores them in the bound field; "" or the problem.
  std::function<std::string(const std::vector<std::string>& texts, bool store)> store_;
  CLI::Option* cli_ = nullptr;  // set by attachOptions
};

class OptionTable {
 public:
  // Declares an option filling `field` (bound by reference: it must outlive the parse). Field
  // types: std::string, int, unsigned long long, double, bool (a flag), std::optional of a
  // scalar (empty: "not given", e.g. "from the scale"), std::vector of a scalar (a list).
  template <typename T>
  Option& add(const std::string& flags, T& field, const std::string& help) {
    Option& o = declare(flags, help);
    o.default_text_ = describe(field);
    if constexpr (std::is_same_v<T, bool>) o.is_flag_ = true;
    o.type_name_ = typeName(static_cast<T*>(nullptr));
    o.is_list_ = isList(static_cast<T*>(nullptr));
    const Option* self = &o;
    o.store_ = [self, &field](const std::vector<std::string>& texts, bool store) {
      return self->assign(field, texts, store);
    };
    return o;
  }
  // Adds `--config FILE`: a key = value file (io/key_value.h) whose keys are the other options'.
  void addConfigFile(std::string& path_field);
  // Keys of the options set explicitly (command line or file) are inserted here after a parse.
  void recordGivenIn(std::set<std::string>& given) { given_ = &given; }

  const std::vector<std::unique_ptr<Option>>& options() const { return options_; }
  const Option* findByKey(const std::string& key) const;

  // Registers every option with CLI11 (names, help with default, number of values).
  void registerWith(CLI::App& command);
  // After CLI11 has parsed the command registerWith was given: reads the config file (if one was named), then applies the
  // command-line values over it, then checks required options. Throws OptionError / ConfigError.
  void resolve();

 private:
  Option& declare(const std::string& flags, const std::string& help);
  // Applies the file's keys not in `from_command_line`; inserts every key it holds into `set`.
  void applyConfigFile(const std::string& path, const std::set<std::string>& from_command_line,
                       std::set<std::string>& set);

  static std::string typeName(const std::string*) { return "TEXT"; }
  static std::string typeName(const int*) { return "INT"; }
  static std::string typeName(const unsigned long long*) { return "UINT"; }
  static std::string typeName(const double*) { return "NUMBER"; }
  static std::string typeName(const bool*) { return ""; }
  template <typename E>
  static std::string typeName(const std::optional<E>*) { return typeName(static_cast<E*>(nullptr)); }
  template <typename E>
  static std::string typeName(const std::vector<E>*) { return typeName(static_cast<E*>(nullptr)); }
  template <typename T>
  static bool isList(const T*) { return false; }
  template <typename E>
  static bool isList(const std::vector<E>*) { return true; }

  static std::string describe(const std::string& v) { return v; }
  static std::string describe(int v) { return std::to_string(v); }
  static std::string describe(unsigned long long v) { return std::to_string(v); }
  static std::string describe(double v);
  static std::optional<std::string> describe(bool) { return std::nullopt; }
  template <typename E>
  static std::optional<std::string> describe(const std::optional<E>& v) {
    if (!v) return std::nullopt;
    return describe(*v);
  }
  template <typename E>
  static std::string describe(const std::vector<E>& v) {
    std::string s;
    for (const E& e : v) s += (s.empty() ? "" : " ") + describe(e);
    return s;
  }

  std::vector<std::unique_ptr<Option>> options_;
  std::string* config_path_ = nullptr;
  std::set<std::string>* given_ = nullptr;
};

// Registers `table`'s options on `command` and resolves them when CLI11 has parsed it (the
// callback keeps the table alive as long as the command).
void attachOptions(CLI::App& command, std::shared_ptr<OptionTable> table);

// Options that another choice makes meaningless (a flag only one mode reads). `given` is the set
// recordGivenIn fills (config keys); `keys` are config keys. firstGiven: the first of them given,
// as its flag ("--max-thrust"), else "". refuseGiven: throws OptionError "--flag: why" for it, so
// a run never silently does something other than what its flags asked for.
std::string firstGiven(const std::set<std::string>& given, std::initializer_list<const char*> keys);
void refuseGiven(const std::set<std::string>& given, std::initializer_list<const char*> keys, const std::string& why);

}  // namespace quadfdi::cli
