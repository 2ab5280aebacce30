#include "io/key_value.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include "io/file_bytes.h"

namespace quadfdi {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

bool validKey(const std::string& key) {
  if (key.empty()) return false;
  for (char c : key)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
  return true;
}

// Removes a '#' comment that is not inside a quoted string.
std::string stripComment(const std::string& line) {
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '"') quoted = !quoted;
    if (line[i] == '#' && !quoted) return line.substr(0, i);
  }
  return line;
}

}  // namespace

bool parseFiniteNumber(const std::string& text, double& value) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE || !std::isfinite(v)) return false;
  // strtod accepts hex floats and "inf"/"nan" spellings; a config should not.
  for (char c : t)
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-'))
      return false;
  value = v;
  return true;
}

const KeyValueEntry* KeyValueDocument::find(const std::string& key) const {
  for (const auto& e : entries)
    if (e.key == key) return &e;
  return nullptr;
}

void KeyValueDocument::fail(const KeyValueEntry& entry, const std::string& problem) const {
  throw ConfigError(source + ":" + std::to_string(entry.line) + ": " + problem);
}

double KeyValueDocument::number(const KeyValueEntry& entry) const {
  double v = 0.0;
  if (!parseFiniteNumber(entry.value, v)) fail(entry, "'" + entry.key + "' needs a finite number, got '" + entry.value + "'");
  return v;
}

long long KeyValueDocument::integer(const KeyValueEntry& entry) const {
  const double v = number(entry);
  if (v != std::floor(v) || std::abs(v) > 9.0e15)
    fail(entry, "'" + entry.key + "' needs an integer, got '" + entry.value + "'");
  return static_cast<long long>(v);
}

bool KeyValueDocument::boolean(const KeyValueEntry& entry) const {
  if (entry.value == "true") return true;
  if (entry.value == "false") return false;
  fail(entry, "'" + entry.key + "' needs true or false, got '" + entry.value + "'");
}

std::string KeyValueDocument::string(const KeyValueEntry& entry) const {
  const std::string& v = entry.value;
  if (v.size() >= 2 && v.front() == '"' && v.back() == '"') return v.substr(1, v.size() - 2);
  if (v.find_first_of("\"[]=") != std::string::npos || v.empty())
    fail(entry, "'" + entry.key + "' needs a string, got '" + v + "'");
  return v;
}

std::vector<double> KeyValueDocument::numberList(const KeyValueEntry& entry) const {
  const std::string& v = entry.value;
  if (v.size() < 2 || v.front() != '[' || v.back() != ']')
    fail(entry, "'" + entry.key + "' needs a list like [1, 2, 3], got '" + v + "'");
  std::vector<double> out;
  const std::string inner = trim(v.substr(1, v.size() - 2));
  if (inner.empty()) return out;
  std::stringstream ss(inner);
  std::string item;
  while (std::getline(ss, item, ',')) {
    double x = 0.0;
    if (!parseFiniteNumber(item, x))
      fail(entry, "'" + entry.key + "' list item '" + trim(item) + "' is not a finite number");
    out.push_back(x);
  }
  return out;
}

KeyValueDocument parseKeyValue(const std::string& text, const std::string& source) {
  KeyValueDocument doc;
  doc.source = source;
  std::set<std::string> seen;
  std::string section;
  std::istringstream in(text);
  std::string raw;
  int line_no = 0;
  auto fail = [&](const std::string& problem) {
    throw ConfigError(source + ":" + std::to_string(line_no) + ": " + problem);
  };
  while (std::getline(in, raw)) {
    ++line_no;
    if (raw.find('\0') != std::string::npos) fail("binary data (NUL byte); not a text config file");
    const std::string line = trim(stripComment(raw));
    if (line.empty()) continue;
    if (line.front() == '[' && line.find('=') == std::string::npos) {
      if (line.back() != ']') fail("section header needs a closing ']'");
      section = trim(line.substr(1, line.size() - 2));
      if (!validKey(section)) fail("invalid section name '" + section + "'");
      continue;
    }
    const auto eq = line.find('=');
    if (eq == std::string::npos) fail("expected 'key = value', got '" + line + "'");
    const std::string key = trim(line.substr(0, eq));
    const std::string value = trim(line.substr(eq + 1));
    if (!validKey(key)) fail("invalid key '" + key + "' (letters, digits, '_', '-', '.')");
    if (value.empty()) fail("key '" + key + "' has no value");
    if (std::count(value.begin(), value.end(), '"') % 2 != 0) fail("unterminated string in value of '" + key + "'");
    const std::string full = section.empty() ? key : section + "." + key;
    if (!seen.insert(full).second) fail("duplicate key '" + full + "'");
    doc.entries.push_back({full, value, line_no});
  }
  return doc;
}

std::string readTextFile(const std::string& path, const std::string& kind, PipeReading pipes) {
  try {
    return readFileBounded(path, kMaxConfigFileBytes, kind, pipes);
  } catch (const FileReadError& e) {
    throw ConfigError(e.what());
  }
}

KeyValueDocument readKeyValueFile(const std::string& path) { return parseKeyValue(readTextFile(path), path); }

}  // namespace quadfdi
