// Keeps lua/README.md, the scene-language reference, in step with what the
// bindings and the prelude register: every registered class, member and
// global must be documented there.
//
// The convention (also stated in a comment at the top of lua/README.md):
// - A class C is documented by a Markdown heading (a line starting with '#',
//   outside code fences) that holds the code span `C` or a code span
//   starting with "C(". Its section runs to the next heading of the same or
//   a higher level; one heading may name several classes that share it.
// - Each attribute, method and operator (a metamethod other than the ones
//   every class gets, e.g. `__add`) of C has a table row in a section of C
//   whose first cell holds a code span containing the name as a whole word
//   (`v:dot(w)` documents dot).
// - Each global the bindings and the prelude add that is not a class (global
//   functions such as Rotate, prelude values and helpers such as x, grey,
//   Floor) has such a table row anywhere in the file.
// Documented names that are not registered are fine (classes being added
// elsewhere may be documented ahead of time); only registered names that the
// reference lacks fail, all listed in one message.
#include "bindings/sandbox.h"
#include "bindings/script_state.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace lray::lua {
namespace {

constexpr const char kReferencePath[] = LRAY_SOURCE_DIR "/lua/README.md";

/// Metamethods that createClass (bindings/lua_binding.cpp) gives every class.
const std::set<std::string> kGenericMetamethods = {
    "__index", "__newindex", "__call", "__tostring", "__name", "__metatable", "__gc"};

/// The names a fresh scene-script state has registered.
struct Registered {
  struct Class {
    std::string name;
    std::vector<std::string> members; ///< attributes, methods, operators
  };
  std::vector<Class> classes;
  std::vector<std::string> globals; ///< added globals that are not classes
};

std::set<std::string> globalNames(lua_State *L) {
  std::set<std::string> names;
  lua_pushglobaltable(L);
  lua_pushnil(L);
  while (lua_next(L, -2) != 0) {
    if (lua_type(L, -2) == LUA_TSTRING) names.insert(lua_tostring(L, -2));
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  return names;
}

Registered registeredNames() {
  ScriptOptions options;
  ScriptState state(".", options);
  lua_State *L = state.state();
  Registered out;
  std::set<std::string> classNames;
  for (const auto &cls : state.context().classes) {
    Registered::Class c{cls->name, cls->memberNames};
    lua_rawgeti(L, LUA_REGISTRYINDEX, cls->metatableRef);
    lua_pushnil(L);
    while (lua_next(L, -2) != 0) {
      if (lua_type(L, -2) == LUA_TSTRING) {
        std::string key = lua_tostring(L, -2);
        if (key.rfind("__", 0) == 0 && !kGenericMetamethods.count(key)) c.members.push_back(key);
      }
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    classNames.insert(c.name);
    out.classes.push_back(std::move(c));
  }
  // What the bindings and the prelude add to the sandbox's own globals.
  lua_State *bare = luaL_newstate();
  openLibraries(bare, options.unsafe);
  std::set<std::string> standard = globalNames(bare);
  lua_close(bare);
  for (const std::string &name : globalNames(L))
    if (!standard.count(name) && !classNames.count(name)) out.globals.push_back(name);
  return out;
}

bool isIdentifierChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

/// `word` occurs in `text` with no identifier character on either side.
bool containsWord(const std::string &text, const std::string &word) {
  for (size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) {
    size_t end = at + word.size();
    if ((at == 0 || !isIdentifierChar(text[at - 1])) &&
        (end == text.size() || !isIdentifierChar(text[end])))
      return true;
  }
  return false;
}

/// The contents of the `code spans` of one line.
std::vector<std::string> codeSpans(const std::string &line) {
  std::vector<std::string> spans;
  size_t open = line.find('`');
  while (open != std::string::npos) {
    size_t close = line.find('`', open + 1);
    if (close == std::string::npos) break;
    spans.push_back(line.substr(open + 1, close - open - 1));
    open = line.find('`', close + 1);
  }
  return spans;
}

/// The first cell of a table row: up to the next '|' that is not escaped as "\|".
std::string firstCell(const std::string &row) {
  size_t end = 1;
  while (end < row.size() && !(row[end] == '|' && row[end - 1] != '\\')) ++end;
  return row.substr(1, end - 1);
}

/// lua/README.md read by the convention above.
class Reference {
public:
  explicit Reference(const std::string &markdown) {
    std::istringstream in(markdown);
    std::string line;
    std::vector<size_t> open; // sections enclosing the current line, outermost first
    bool fenced = false;
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.rfind("```", 0) == 0 || line.rfind("~~~", 0) == 0) {
        fenced = !fenced;
        continue;
      }
      if (fenced || line.empty()) continue;
      if (line[0] == '#') {
        size_t level = line.find_first_not_of('#');
        if (level == std::string::npos) level = line.size();
        while (!open.empty() && sections_[open.back()].level >= level) open.pop_back();
        open.push_back(sections_.size());
        sections_.push_back({level, codeSpans(line), {}});
      } else if (line[0] == '|') {
        for (const std::string &span : codeSpans(firstCell(line))) {
          rowNames_.push_back(span);
          for (size_t s : open) sections_[s].rowNames.push_back(span);
        }
      }
    }
  }

  /// Whether some heading names the class.
  bool hasClass(const std::string &cls) const { return !sectionsOf(cls).empty(); }

  /// Whether a section of `cls` has a row for `member`.
  bool hasMember(const std::string &cls, const std::string &member) const {
    for (const Section *s : sectionsOf(cls))
      if (anyContains(s->rowNames, member)) return true;
    return false;
  }

  /// Whether any row documents `name`.
  bool hasGlobal(const std::string &name) const { return anyContains(rowNames_, name); }

private:
  struct Section {
    size_t level;
    std::vector<std::string> headingSpans;
    std::vector<std::string> rowNames; ///< code spans of first cells of rows inside it
  };

  std::vector<const Section *> sectionsOf(const std::string &cls) const {
    std::vector<const Section *> found;
    for (const Section &s : sections_)
      for (const std::string &span : s.headingSpans)
        if (span == cls || span.rfind(cls + "(", 0) == 0) {
          found.push_back(&s);
          break;
        }
    return found;
  }

  static bool anyContains(const std::vector<std::string> &spans, const std::string &name) {
    for (const std::string &span : spans)
      if (containsWord(span, name)) return true;
    return false;
  }

  std::vector<Section> sections_;
  std::vector<std::string> rowNames_;
};

/// Every registered name the reference lacks, one per entry.
std::vector<std::string> undocumented(const Registered &registered, const Reference &reference) {
  std::vector<std::string> missing;
  for (const Registered::Class &c : registered.classes) {
    if (!reference.hasClass(c.name)) {
      missing.push_back("class " + c.name + " (no heading with `" + c.name + "`)");
      continue;
    }
    for (const std::string &member : c.members)
      if (!reference.hasMember(c.name, member)) missing.push_back(c.name + "." + member);
  }
  for (const std::string &name : registered.globals)
    if (!reference.hasGlobal(name)) missing.push_back("global " + name);
  return missing;
}

std::string readReference() {
  std::ifstream in(kReferencePath, std::ios::binary);
  EXPECT_TRUE(in) << "cannot read " << kReferencePath;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The markdown without the table rows whose first cell documents `name`.
std::string withoutRowsFor(const std::string &markdown, const std::string &name) {
  std::istringstream in(markdown);
  std::string line, out;
  while (std::getline(in, line)) {
    bool drop = false;
    if (!line.empty() && line[0] == '|')
      for (const std::string &span : codeSpans(firstCell(line)))
        drop = drop || containsWord(span, name);
    if (!drop) out += line + "\n";
  }
  return out;
}

std::string joined(const std::vector<std::string> &list) {
  std::string text;
  for (const std::string &s : list) text += "\n  " + s;
  return text;
}

TEST(LanguageReferenceTest, FindsTheRegisteredNames) {
  // Guards the walk itself: an empty walk would make the main test vacuous.
  Registered registered = registeredNames();
  auto hasMember = [&](const std::string &name, const std::string &member) {
    for (const Registered::Class &c : registered.classes)
      if (c.name == name)
        for (const std::string &m : c.members)
          if (m == member) return true;
    return false;
  };
  EXPECT_TRUE(hasMember("Finish", "diffuse"));   // an attribute
  EXPECT_TRUE(hasMember("Mesh", "vertices"));    // a property
  EXPECT_TRUE(hasMember("Scene", "add_entity")); // a method
  EXPECT_TRUE(hasMember("Vector", "__add"));     // an operator
  EXPECT_FALSE(hasMember("Sphere", "__index"));  // generic metamethods are left out
  auto hasGlobal = [&](const std::string &name) {
    for (const std::string &g : registered.globals)
      if (g == name) return true;
    return false;
  };
  EXPECT_TRUE(hasGlobal("Rotate"));        // a typed global function
  EXPECT_TRUE(hasGlobal("mesh_from_obj")); // a raw global function
  EXPECT_TRUE(hasGlobal("grey"));          // a prelude helper
  EXPECT_TRUE(hasGlobal("origin"));        // a prelude value
  EXPECT_FALSE(hasGlobal("Sphere"));       // constructors count as classes
  EXPECT_FALSE(hasGlobal("print"));        // the sandbox's own library
}

TEST(LanguageReferenceTest, DocumentsEveryRegisteredClassMemberAndGlobal) {
  std::vector<std::string> missing = undocumented(registeredNames(), Reference(readReference()));
  EXPECT_TRUE(missing.empty())
      << "lua/README.md does not document these registered names (see the convention at the "
         "top of tests/bindings/language_reference_test.cpp):"
      << joined(missing);
}

TEST(LanguageReferenceTest, FailsWhenARowIsRemoved) {
  std::string markdown = withoutRowsFor(readReference(), "diffuse");
  std::vector<std::string> missing = undocumented(registeredNames(), Reference(markdown));
  EXPECT_NE(std::find(missing.begin(), missing.end(), "Finish.diffuse"), missing.end())
      << joined(missing);
}

TEST(LanguageReferenceTest, ConventionSectionsRowsAndWords) {
  Registered registered{{{"Sphere", {"texture", "open"}},
                         {"Vector", {"dot", "cross", "__add"}},
                         {"Light", {"rows"}}},
                        {"grey", "Floor"}};
  const std::string markdown = "# Reference\n"
                               "## `Sphere(t)`, `Cube`\n"
                               "| `texture` | Texture |\n"
                               "### Details\n"
                               "| `s.open` | in a subsection: still Sphere's |\n"
                               "## `Vector`\n"
                               "| `v:dot(w)` | a whole word |\n"
                               "| `crossed` | not a whole word |\n"
                               "| text and `__add` | any span of the first cell | `cross` |\n"
                               "```\n"
                               "## `Light`\n"
                               "```\n"
                               "| `rows` | inside Vector's section, not Light's |\n"
                               "| `grey(a)` | a global |\n";
  EXPECT_EQ(joined(undocumented(registered, Reference(markdown))),
            joined({"Vector.cross", "class Light (no heading with `Light`)", "global Floor"}));
}

} // namespace
} // namespace lray::lua
