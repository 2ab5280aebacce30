#include "cli/options.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "cli/shipped_files.h"
#include "io/key_value.h"
#include "model/vehicle_params.h"

namespace quadfdi::cli {
namespace {

std::string quoted(const std::string& text) { return "'" + text + "'"; }

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

bool allDigits(const std::string& text) {
  const std::size_t first = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
  if (first == text.size()) return false;
  return std::all_of(text.begin() + static_cast<std::ptrdiff_t>(first), text.end(),
                     [](char c) { return c >= '0' && c <= '9'; });
}

// An integer, written plainly or as an integral decimal (1e3, 2.0) as config files allow.
std::string parseInteger(const std::string& text, long double low, long double high, const char* what,
                         long double& value) {
  const std::string problem = std::string("needs ") + what + ", got " + quoted(text);
  if (allDigits(text)) {
    errno = 0;
    char* end = nullptr;
    if (text[0] == '-') {
      const long long v = std::strtoll(text.c_str(), &end, 10);
      if (errno == ERANGE) return problem;
      value = static_cast<long double>(v);
    } else {
      const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
      if (errno == ERANGE) return problem;
      value = static_cast<long double>(v);
    }
  } else {
    double v = 0.0;
    if (!parseFiniteNumber(text, v) || v != std::floor(v) || std::abs(v) > 9.0e15) return problem;
    value = static_cast<long double>(v);
  }
  if (value < low || value > high) return problem;
  return {};
}

// The config file's value as the texts the command line would have given.
std::vector<std::string> configTexts(const KeyValueDocument& doc, const KeyValueEntry& e, const Option& o) {
  const std::string& v = e.value;
  if (v.empty() || v.front() != '[') return {doc.string(e)};
  if (v.back() != ']') doc.fail(e, o.key() + ": a list needs a closing ']'");
  std::vector<std::string> texts;
  std::string inner = v.substr(1, v.size() - 2);
  if (inner.find_first_not_of(" \t") == std::string::npos) return texts;
  std::stringstream items(inner);
  for (std::string item; std::getline(items, item, ',');) {
    const auto b = item.find_first_not_of(" \t");
    const auto en = item.find_last_not_of(" \t");
    item = b == std::string::npos ? std::string() : item.substr(b, en - b + 1);
    if (item.size() >= 2 && item.front() == '"' && item.back() == '"') item = item.substr(1, item.size() - 2);
    if (item.empty()) doc.fail(e, o.key() + ": empty list item");
    texts.push_back(item);
  }
  return texts;
}

// The number of values `texts` has against what `o` takes; "" or the problem.
std::string countProblem(const std::vector<std::string>& texts, bool is_list, int exact) {
  if (!is_list) return texts.size() == 1 ? "" : "needs a single value, got " + std::to_string(texts.size());
  if (exact > 0 && static_cast<int>(texts.size()) != exact)
    return "needs " + std::to_string(exact) + " values, got " + std::to_string(texts.size());
  if (texts.empty()) return "needs at least one value";
  return {};
}

}  // namespace

std::string parseOptionValue(const std::string& text, std::string& value) {
  value = text;
  return {};
}

std::string parseOptionValue(const std::string& text, int& value) {
  long double v = 0;
  if (std::string p = parseInteger(text, std::numeric_limits<int>::min(), std::numeric_limits<int>::max(),
                                   "an integer", v);
      !p.empty())
    return p;
  value = static_cast<int>(v);
  return {};
}

std::string parseOptionValue(const std::string& text, unsigned long long& value) {
  if (allDigits(text) && text[0] != '-') {  // exact, also above 2^53
    errno = 0;
    const unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
    if (errno == ERANGE) return "needs an integer >= 0, got " + quoted(text);
    value = v;
    return {};
  }
  long double v = 0;
  if (std::string p = parseInteger(text, 0, 9.0e15L, "an integer >= 0", v); !p.empty()) return p;
  value = static_cast<unsigned long long>(v);
  return {};
}

std::string parseOptionValue(const std::string& text, double& value) {
  if (!parseFiniteNumber(text, value)) return "needs a finite number, got " + quoted(text);
  return {};
}

std::string parseOptionValue(const std::string& text, bool& value) {
  if (text == "true") value = true;
  else if (text == "false") value = false;
  else return "needs true or false, got " + quoted(text);
  return {};
}

Option& Option::choices(std::vector<std::string> allowed) {
  choices_ = std::move(allowed);
  type_name_.clear();
  for (const std::string& c : choices_) type_name_ += (type_name_.empty() ? "" : "|") + c;
  return *this;
}

Option& Option::range(double low, double high) {
  low_ = low;
  high_ = high;
  low_open_ = false;
  return *this;
}

Option& Option::atLeast(double low) { return range(low, std::numeric_limits<double>::infinity()); }

Option& Option::above(double low, double high) {
  range(low, high);
  low_open_ = true;
  return *this;
}

Option& Option::check(std::function<std::string(const std::string&)> problem_of) {
  check_ = std::move(problem_of);
  return *this;
}

Option& Option::values(int n) {
  exact_count_ = n;
  return *this;
}

Option& Option::required() {
  required_ = true;
  return *this;
}

Option& Option::defaultText(std::string text) {
  default_text_ = std::move(text);
  return *this;
}

Option& Option::shippedFile() {
  file_kind_ = FileKind::kShipped;
  return *this;
}

Option& Option::vehicleFile() {
  file_kind_ = FileKind::kVehicle;
  return *this;
}

Option& Option::paramsFile() {
  file_kind_ = FileKind::kParams;
  return *this;
}

std::string Option::fileText(const std::string& given, std::string& problem) const {
  if (file_kind_ == FileKind::kShipped) return cli::shippedFile(given);
  if (file_kind_ == FileKind::kParams && isNamedParamSet(given)) return given;
  const std::string text = cli::vehicleFile(given, &problem);
  if (!problem.empty() && file_kind_ == FileKind::kParams)
    problem = "not nominal, perturbed or perturbed-strong; " + problem;
  return text;
}

std::string Option::checkText(const std::string& text) const {
  if (!choices_.empty() && std::find(choices_.begin(), choices_.end(), text) == choices_.end()) {
    std::string list;
    for (const std::string& c : choices_) list += (list.empty() ? "" : ", ") + c;
    return quoted(text) + " is not one of: " + list;
  }
  return check_ ? check_(text) : std::string();
}

std::string Option::checkNumber(double v) const {
  const bool low_ok = low_open_ ? v > low_ : v >= low_;
  if (low_ok && v <= high_) return {};
  const bool bounded_low = std::isfinite(low_), bounded_high = std::isfinite(high_);
  std::string want;
  if (bounded_low && bounded_high)
    want = "in " + std::string(low_open_ ? "(" : "[") + number(low_) + ", " + number(high_) + "]";
  else if (bounded_low)
    want = (low_open_ ? "> " : ">= ") + number(low_);
  else
    want = "<= " + number(high_);
  return "must be " + want + ", got " + number(v);
}

std::string OptionTable::describe(double v) { return number(v); }

Option& OptionTable::declare(const std::string& flags, const std::string& help) {
  auto o = std::make_unique<Option>();
  o->flags_ = flags;
  o->help_ = help;
  std::stringstream names(flags);
  for (std::string name; std::getline(names, name, ',');)
    if (name.rfind("--", 0) == 0 && o->long_flag_.empty()) o->long_flag_ = name;
  if (o->long_flag_.empty()) throw std::logic_error("option '" + flags + "' has no long name");
  o->key_ = o->long_flag_.substr(2);
  std::replace(o->key_.begin(), o->key_.end(), '-', '_');
  if (findByKey(o->key_) || o->key_ == "config") throw std::logic_error("option '" + flags + "' declared twice");
  options_.push_back(std::move(o));
  return *options_.back();
}

void OptionTable::addConfigFile(std::string& path_field) { config_path_ = &path_field; }

const Option* OptionTable::findByKey(const std::string& key) const {
  for (const auto& o : options_)
    if (o->key_ == key) return o.get();
  return nullptr;
}

void OptionTable::registerWith(CLI::App& command) {
  if (config_path_)
    command.add_option("--config", *config_path_,
                       "Configuration file: key = value lines whose keys are the long flags without '--', "
                       "'-' → '_' (configs/*.toml); flags given on the command line win");
  for (const auto& o : options_) {
    std::string help = o->help_;
    if (o->default_text_ && !o->default_text_->empty()) help += " (default: " + *o->default_text_ + ")";
    if (o->is_flag_) {
      o->cli_ = command.add_flag(o->flags_)->description(help);
      continue;
    }
    o->cli_ = command.add_option(o->flags_)->description(help);
    o->cli_->type_name(o->type_name_);
    if (o->is_list_) {
      if (o->exact_count_ > 0) o->cli_->expected(o->exact_count_);
      else o->cli_->expected(CLI::detail::expected_max_vector_size);  // one or more, also extra args
    }
  }
}

void OptionTable::applyConfigFile(const std::string& path, const std::set<std::string>& from_command_line,
                                  std::set<std::string>& set) {
  const KeyValueDocument doc = readKeyValueFile(path);
  for (const KeyValueEntry& e : doc.entries) {
    const Option* o = findByKey(e.key);
    if (!o) doc.fail(e, "unknown key '" + e.key + "'");
    const std::vector<std::string> texts = configTexts(doc, e, *o);
    std::string problem = countProblem(texts, o->is_list_, o->exact_count_);
    // Checked even when the command line overrides it: a file is valid or not.
    if (problem.empty()) problem = o->store_(texts, from_command_line.count(o->key_) == 0);
    if (!problem.empty()) doc.fail(e, o->key_ + ": " + problem);
    set.insert(o->key_);
  }
}

void OptionTable::resolve() {
  std::set<std::string> from_command_line, set;
  for (const auto& o : options_)
    if (o->cli_ && o->cli_->count() > 0) from_command_line.insert(o->key_);
  if (config_path_ && !config_path_->empty()) applyConfigFile(shippedFile(*config_path_), from_command_line, set);
  for (const auto& o : options_) {
    if (from_command_line.count(o->key_) == 0) continue;
    const std::vector<std::string> texts = o->is_flag_ ? std::vector<std::string>{"true"} : o->cli_->results();
    std::string problem = countProblem(texts, o->is_list_, o->exact_count_);
    if (problem.empty()) problem = o->store_(texts, true);
    if (!problem.empty()) throw OptionError(o->long_flag_ + ": " + problem);
    set.insert(o->key_);
  }
  for (const auto& o : options_)
    if (o->required_ && set.count(o->key_) == 0)
      throw OptionError(o->long_flag_ + ": required" +
                        (config_path_ ? " (on the command line, or as '" + o->key_ + "' in --config)" : std::string()));
  if (given_) given_->insert(set.begin(), set.end());
}

void attachOptions(CLI::App& command, std::shared_ptr<OptionTable> table) {
  table->registerWith(command);
  command.callback([table] { table->resolve(); });
}

std::string firstGiven(const std::set<std::string>& given, std::initializer_list<const char*> keys) {
  for (const char* key : keys)
    if (given.count(key)) {
      std::string flag = std::string("--") + key;
      std::replace(flag.begin(), flag.end(), '_', '-');
      return flag;
    }
  return {};
}

void refuseGiven(const std::set<std::string>& given, std::initializer_list<const char*> keys, const std::string& why) {
  if (const std::string flag = firstGiven(given, keys); !flag.empty()) throw OptionError(flag + ": " + why);
}

}  // namespace quadfdi::cli
