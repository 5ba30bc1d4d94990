// Fuzz target (libFuzzer): hostile scene scripts (issue 23). The input bytes
// are read as a tiny program that writes a Lua script which attacks the
// script layer rather than the LRay classes: big and repeated allocations
// (string.rep up to 2^63, growing tables, table.concat, string.format with
// wide fields, concatenation in loops, LRay objects by the thousand), deep
// recursion (Lua, pcall, xpcall, metamethod chains, nested error handlers,
// parser nesting through load), the sandboxed library with odd arguments
// (patterns, string.pack, utf8, table.*, math, tonumber, load, the io/os
// wrappers, metatables with __index/__newindex/__call/__close/__gc...),
// error objects of every type, and reads of files outside the scene's
// folder. Each statement runs under pcall; a memory limit (256 KiB to
// 64 MiB, mostly 1 MiB) and a 0.25 s timeout bound each input, and every
// C call's arguments are bounded so that none runs for seconds (the
// watchdog would end the process). The script then goes through
// SceneScript::fromString and, when it defines scene(clock), buildFrame.
// Its folder is a fresh temporary one (a few files, a FIFO, links in and
// out); SCRIPT_FUZZ_PRINT=1 prints each script, its limit and outcome.
//
// A SceneError is fine. A crash, a sanitizer or leak report, another
// exception, or a sandbox escape is a bug: the script checks in Lua that
// refused things stay refused (a file outside the folder opened, a write
// mode accepted, a forbidden library present, a binary chunk loaded, a __gc
// finalizer installed) and then raises an error carrying "SANDBOX_ESCAPE",
// which aborts here.
#include "bindings/scene_script.h"

#include <fuzzer/FuzzedDataProvider.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

namespace {

std::string gBaseDir; // the scene's folder: a fresh temporary folder per process

void removeBaseDir() {
  if (gBaseDir.empty()) return;
  std::error_code ec;
  std::filesystem::remove_all(gBaseDir, ec);
}

void writeFile(const std::string &name, const std::string &text) {
  std::ofstream(gBaseDir + "/" + name, std::ios::binary) << text;
}

/// The scene folder: a few files a script may read, a folder, a FIFO (must
/// be refused, never opened: opening one would block) and symbolic links
/// into and out of the folder.
void makeBaseDir() {
  char tmpl[] = "/tmp/lray-script-fuzz-XXXXXX";
  if (!mkdtemp(tmpl)) {
    std::perror("mkdtemp");
    std::abort();
  }
  gBaseDir = tmpl;
  std::atexit(&removeBaseDir);
  writeFile("data.txt", "line one\n42 3.5 0x10 -7\n\nlast line without newline");
  writeFile("mod.lua", "local n = ... return {n = n, f = function(a) return a end}\n");
  writeFile("scene.lua", "function scene(clock) return Scene() end\nreturn 1\n");
  writeFile("bad.lua", "return +\n");
  // Nested dofile is Lua-to-Lua (no C stack), so without a cap it would
  // read the file until the timeout.
  writeFile("self.lua", "DEPTH = (DEPTH or 0) + 1\nif DEPTH > 100 then error('deep') end\n"
                        "return (dofile('self.lua'))\n");
  writeFile("error.lua", "error(setmetatable({}, {__tostring = function() return 'obj' end}))\n");
  writeFile("empty.lua", "");
  writeFile("binary.lua", std::string("\x1bLua\x54\x00\x19\x93\r\n\x1a\n\x04\x08\x08", 15));
  writeFile("mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1 2 3\n");
  std::filesystem::create_directory(gBaseDir + "/sub");
  writeFile("sub/x.lua", "return 'sub'\n");
  std::error_code ec;
  std::filesystem::create_symlink("/etc/passwd", gBaseDir + "/link_out", ec);
  std::filesystem::create_symlink("data.txt", gBaseDir + "/link_in", ec);
  std::filesystem::create_directory_symlink("/etc", gBaseDir + "/etc_link", ec);
  mkfifo((gBaseDir + "/pipe").c_str(), 0600);
}

// ---- literals -----------------------------------------------------------------

const char *const kNumbers[] = {"0",
                                "1",
                                "-1",
                                "2",
                                "3",
                                "0.5",
                                "-0.0",
                                "100",
                                "255",
                                "256",
                                "1e5",
                                "2^31",
                                "2^53",
                                "2^63",
                                "math.maxinteger",
                                "math.mininteger",
                                "-(2^63)",
                                "0x7fffffff",
                                "0xffffffff",
                                "0/0",
                                "1/0",
                                "-1/0",
                                "1e308",
                                "5e-324",
                                "math.pi",
                                "-2^31",
                                "1.5"};

const char *const kStrings[] = {"''",
                                "'a'",
                                "'abc'",
                                "'hello world'",
                                "'\\0\\1\\2'",
                                "'\\xff\\xfe\\x80'",
                                "'\\u{10FFFF}'",
                                "'\\u{7FFFFFFF}'",
                                "'%d'",
                                "'1e2'",
                                "'0x10'",
                                "'  12  '",
                                "'inf'",
                                "'nan'",
                                "'data.txt'",
                                "string.rep('ab', 12)",
                                "'h\\195\\169llo'",
                                "'a\\0b'",
                                "'%'",
                                "'(('",
                                "'0x1p4'",
                                "'-0'",
                                "'\\n'"};

/// Strings to repeat: not the empty one. Lua 5.4.4's string.rep loops n
/// times even when each copy is empty: string.rep('', 2^26) takes 1.5 s
/// under ASan and string.rep('', 2^40) only ends when the watchdog ends
/// the process (a hostile script's way past the hook, reported with this
/// target; not a crash).
const char *const kRepStrings[] = {"'a'",     "'abc'", "'hello world'",        "'\\0\\1\\2'",
                                   "'\\xff'", "'%d'",  "string.rep('ab', 12)", "'h\\195\\169llo'",
                                   "'\\n'"};

/// Sizes for string.rep, loops and ranges: tiny to far past any limit.
const char *const kSizes[] = {"0",
                              "1",
                              "3",
                              "100",
                              "4096",
                              "65536",
                              "2^20",
                              "2^22",
                              "2^24",
                              "2^25",
                              "2^26",
                              "2^30",
                              "2^31",
                              "2^32",
                              "2^40",
                              "2^53",
                              "math.maxinteger",
                              "-1",
                              "math.mininteger",
                              "0/0",
                              "1.5",
                              "1e308",
                              "1/0",
                              "'10'",
                              "nil",
                              "{}"};

/// Loop counts: bounded so that a loop ends (or meets the memory limit)
/// well within the timeout, also when earlier statements made the
/// collector thrash ('stop', 'setpause').
const char *const kCounts[] = {"0", "1", "10", "100", "1000", "10000", "30000"};
/// Loop counts for LRay objects (each a userdata and C++ work).
const char *const kObjectCounts[] = {"0", "1", "10", "100", "1000", "3000"};

/// Subjects of pattern searches: at most 24 bytes, so that no pattern of
/// at most four items backtracks for long.
const char *const kSubjects[] = {"''",
                                 "'a'",
                                 "'abc'",
                                 "'hello world'",
                                 "'aaaaaaaaaaaaaaaaaaaaaaaa'",
                                 "'(a(b)c)((d)'",
                                 "'12 34 0x5f -6.5e2'",
                                 "'\\0a\\0b\\0'",
                                 "'\\xff\\xfe\\xc3\\xa9\\xe2\\x82'",
                                 "'k=v, x=y;'",
                                 "'%%%%[[]]^^$$'",
                                 "'THE end.'",
                                 "'ababababababababababab'",
                                 "'\\t \\n\\r'"};

/// Pattern items; a pattern is one to four of these (malformed ones too).
const char *const kPatternItems[] = {
    ".",  "a",      "b",   "%a",    "%d",   "%s",   "%w", "%x",     "%p",      "%c",   "%g",
    "%u", "%l",     "%z",  "%",     "%b()", "%bab", "%b", "%f[%w]", "%f[^%a]", "%f",   "[",
    "]",  "[^a-z]", "[a-", "[%a_]", "[]",   "[^]",  "(",  ")",      "()",      "(.)",  "%1",
    "%2", "%0",     "^",   "$",     "*",    "+",    "-",  "?",      ".-",      ".*",   "a+",
    "a*", "a-",     "x?",  "[ab]*", "(a*)", "%%",   "%]", "[%]]",   "\\0",     "\\xff"};

const char *const kFormats[] = {"'%d'",
                                "'%5.2f'",
                                "'%99d'",
                                "'%-99s'",
                                "'%099.99f'",
                                "'%.99f'",
                                "'%99.99e'",
                                "'%a'",
                                "'%A'",
                                "'%q'",
                                "'%g'",
                                "'%i'",
                                "'%c'",
                                "'%x'",
                                "'%X'",
                                "'%o'",
                                "'%u'",
                                "'%s%s%s'",
                                "'%10.3s'",
                                "'%#x'",
                                "'%+.0f'",
                                "'% d'",
                                "'%100d'",
                                "'%.100f'",
                                "'%5$d'",
                                "'%'",
                                "'%%'",
                                "'%z'",
                                "'%-+ #0d'",
                                "'%99.99g'",
                                "'%.3q'",
                                "'%p'",
                                "'%s'",
                                "string.rep('%s', 60)",
                                "string.rep('%99d', 30)",
                                "'%99.99f'"};

/// string.pack/unpack/packsize formats are a few of these items.
const char *const kPackItems[] = {"<",
                                  ">",
                                  "=",
                                  "!",
                                  "!8",
                                  "!3",
                                  "!17",
                                  "b",
                                  "B",
                                  "h",
                                  "H",
                                  "i",
                                  "i3",
                                  "i8",
                                  "i16",
                                  "i17",
                                  "i0",
                                  "I7",
                                  "l",
                                  "L",
                                  "j",
                                  "J",
                                  "T",
                                  "f",
                                  "d",
                                  "n",
                                  "s",
                                  "s1",
                                  "s16",
                                  "z",
                                  "x",
                                  "X",
                                  "Xi8",
                                  "Xz",
                                  "c3",
                                  "c0",
                                  "c",
                                  "c99999999999",
                                  "c2147483647",
                                  " ",
                                  "%"};

/// Paths a sandboxed script must never open.
const char *const kOutsidePaths[] = {"'/etc/passwd'",
                                     "'../x'",
                                     "'..'",
                                     "'/dev/zero'",
                                     "'/dev/stdin'",
                                     "'/proc/self/mem'",
                                     "'/proc/self/environ'",
                                     "'link_out'",
                                     "'sub'",
                                     "'.'",
                                     "''",
                                     "'pipe'",
                                     "'sub/../../x'",
                                     "'/tmp'",
                                     "'//etc//passwd'",
                                     "'sub/../../../../etc/passwd'",
                                     "'/nonexistent/x'",
                                     "'etc_link/passwd'",
                                     "base_ .. '/../x'",
                                     "base_ .. '/link_out'",
                                     "base_ .. '/pipe'",
                                     "'../' .. string.rep('../', 40) .. 'etc/passwd'",
                                     "'/'"};

/// Paths inside the folder (some missing, some not Lua, one with a NUL
/// that C truncates to data.txt).
const char *const kInsidePaths[] = {"'data.txt'",
                                    "'mod.lua'",
                                    "'missing.lua'",
                                    "'sub/x.lua'",
                                    "'link_in'",
                                    "'empty.lua'",
                                    "'bad.lua'",
                                    "'scene.lua'",
                                    "'self.lua'",
                                    "'error.lua'",
                                    "'binary.lua'",
                                    "'mesh.obj'",
                                    "'data.txt\\0/etc/passwd'",
                                    "base_ .. '/data.txt'",
                                    "'./sub/../mod.lua'",
                                    "string.rep('a', 300) .. '.lua'",
                                    "'sub/'"};

/// Chunks for load: junk, binary signatures, parser limits. (No endless
/// loop: each would cost the whole 0.25 s timeout, which dominated the
/// fuzzer's time; the timeout has its own tests in tests/hostile.)
const char *const kChunks[] = {"'return 1'",
                               "'return ...'",
                               "'return'",
                               "'return 1 +'",
                               "'x = '",
                               "'[['",
                               "'--[==['",
                               "'\\0'",
                               "'\\27Lua'",
                               "'\\27Lua\\x54\\0'",
                               "'goto x'",
                               "'::a:: ::a::'",
                               "'local x <close> = 1'",
                               "'local x <foo> = 1'",
                               "'local x <const> = 1; x = 2'",
                               "'return 0x'",
                               "'return 1e99999'",
                               "'return \"\\\\u{110000}\"'",
                               "'return \"\\\\u{7FFFFFFF}\"'",
                               "'return \"\\\\u{80000000}\"'",
                               "'break'",
                               "'return function(...) local a, b = ... end'",
                               "'local _ENV <const> = {}; return x'",
                               "'return \"\\\\xZZ\"'",
                               "'return \"\\\\999\"'",
                               "'return 1 // 0'",
                               "'return math.mininteger // -1'",
                               "'return 1 << 64, 1 >> -1, ~0'",
                               "'for i = 1, 2, 0 do end'",
                               "'for i = math.maxinteger - 1, math.maxinteger do end'",
                               "'return #{...}'",
                               "'return select(\"#\", ...)'",
                               "'error(...)'",
                               "'error()'",
                               "'local t = {} t[1 << 62] = 1 return #t'",
                               "string.dump(function() return 1 end)",
                               "string.dump(load('return 2'), true)",
                               "'return ' .. string.rep('{', 198) .. string.rep('}', 198)"};

/// Nested text for load: prefix and suffix repeated N times around a core.
struct Nesting {
  const char *prefix, *core, *suffix;
};
const Nesting kNestings[] = {
    {"{", "", "}"},
    {"(", "1", ")"},
    {"-", "1", ""},
    {"not ", "nil", ""},
    {"function() return ", "1", " end"},
    {"do ", "", " end"},
    {"if x then ", "", " end"},
    {"{{", "1", "}}"},
    {"", "1", " .. 1"},
    {"2^", "2", ""},
    {"", "1", " + 1"},
    {"a.", "b", ""},
    {"f(", "", ")"},
    {"{x = ", "1", "}"},
    {"[[", "", "]]"},
    {"(function(...) return ", "...", " end)(1)"},
    {"local a = 1 ", "", ""},
    {"", "a", ", a"},
    {"while false do ", "", " end"},
    {"repeat ", "", " until true"},
};
const char *const kNestCounts[] = {"1",   "10",  "100", "150",  "198",   "199",
                                   "200", "201", "250", "1000", "10000", "100000"};

const char *const kMetaKeys[] = {
    "__index", "__newindex", "__call", "__close",     "__gc",    "__tostring", "__name", "__len",
    "__eq",    "__lt",       "__le",   "__concat",    "__unm",   "__add",      "__idiv", "__band",
    "__shl",   "__bnot",     "__mode", "__metatable", "__pairs", "__mod",      "__pow"};

const char *const kMetaValues[] = {"function(...) return ... end",
                                   "function(t, k) return t[k] end",
                                   "function(t, k, v) t[k] = v end",
                                   "function(t, ...) return t(...) end",
                                   "function() error(E_) end",
                                   "function() return {} end",
                                   "function() return 2^63 end",
                                   "function() return 'x' end",
                                   "function() return nil end",
                                   "function(o, e) error(e) end",
                                   "function(a, b) return a < b end",
                                   "function(a) return #a end",
                                   "{}",
                                   "'k'",
                                   "'kv'",
                                   "42",
                                   "true",
                                   "'locked'",
                                   "setmetatable({}, {__index = function() return 1 end})",
                                   "function() return next, {}, nil end",
                                   "function() return 1, 2, 3 end"};

const char *const kErrorObjects[] = {
    "nil",
    "'msg'",
    "42",
    "0/0",
    "{}",
    "true",
    "function() end",
    "S",
    "Vector(1, 2, 3)",
    "setmetatable({}, {__tostring = function() return 'tostring' end})",
    "setmetatable({}, {__tostring = function() error('in __tostring') end})",
    "setmetatable({}, {__tostring = function() return {} end})",
    "setmetatable({}, {__tostring = function(o) return tostring(o) end})",
    "setmetatable({}, {__name = 'Named'})",
    "string.rep('e', 1000)",
    "io.open('data.txt')",
    "E_",
    "v[1]",
    "coroutine"};

const char *const kCloseBodies[] = {"",
                                    "error(E_)",
                                    "return 1",
                                    "error(E_, 2)",
                                    "v[1] = string.rep('c', 2^20)",
                                    "local y <close> = x"};

const char *const kReadFormats[] = {"'a'",  "'l'", "'L'",  "'n'",  "0",  "1",   "2^20", "2^31",
                                    "2^62", "'x'", "'*a'", "'*l'", "-1", "0/0", "'nn'"};

const char *const kDateFormats[] = {"'%c'", "'*t'", "'!*t'",      "'%Ez'",
                                    "'%'",  "'%Q'", "'%Y-%m-%d'", "string.rep('%c', 1000)",
                                    "''",   "'%E'", "'%Oy'",      "'!%H'"};

const char *const kTimes[] = {
    "0",     "-1", "2^55", "2^62", "1e308", "0/0", "nil", "1700000000", "math.mininteger",
    "-2^40", "'x'"};

class Writer {
public:
  explicit Writer(FuzzedDataProvider &in) : in_(in) {}

  std::string slot() { return "v[" + std::to_string(in_.ConsumeIntegralInRange(1, 6)) + "]"; }

  /// Any value. Huge values come only from slots (earlier statements).
  std::string value(int depth = 0) {
    if (depth > 2 || in_.remaining_bytes() == 0) return pick(kNumbers);
    switch (in_.ConsumeIntegralInRange(0, 11)) {
    case 0:
    case 1:
      return pick(kNumbers);
    case 2:
    case 3:
      return pick(kStrings);
    case 4:
      return slot();
    case 5:
      return "{" + value(depth + 1) + ", " + value(depth + 1) + "}";
    case 6:
      return metaObject(depth + 1);
    case 7:
      return pick(kErrorObjects);
    case 8: {
      const char *const others[] = {"nil",
                                    "true",
                                    "false",
                                    "S",
                                    "_G",
                                    "string",
                                    "Vector(1, 2, 3)",
                                    "Sphere()",
                                    "function() end",
                                    "tostring",
                                    "io.open('data.txt')",
                                    "{n = 1}",
                                    "v",
                                    "math.huge",
                                    "utf8.charpattern"};
      return pick(others);
    }
    case 9:
      return "string.rep(" + pick(kStrings) + ", " +
             std::to_string(in_.ConsumeIntegralInRange(0, 3000)) + ")";
    case 10:
      return "(" + value(depth + 1) + ")";
    default:
      return std::to_string(in_.ConsumeIntegral<int32_t>());
    }
  }

  /// A table with a metatable of one to three random fields.
  std::string metaObject(int depth) {
    std::string mt = "{";
    int n = in_.ConsumeIntegralInRange(1, 3);
    for (int i = 0; i < n; ++i) {
      mt += std::string(i ? ", " : "") + pick(kMetaKeys) + " = ";
      mt += (depth < 2 && in_.ConsumeIntegralInRange(0, 5) == 0) ? metaObject(depth + 1)
                                                                 : std::string(pick(kMetaValues));
    }
    return "setmetatable({" + (in_.ConsumeBool() ? std::string() : "1, 2, 'x'") + "}, " + mt + "})";
  }

  std::string pattern() {
    std::string p;
    int n = in_.ConsumeIntegralInRange(1, 4);
    for (int i = 0; i < n; ++i) {
      std::string item = pick(kPatternItems);
      // Escape for a single-quoted Lua string (backslash items are Lua escapes).
      for (char c : item)
        if (c == '\'')
          p += "\\'";
        else
          p += c;
    }
    return "'" + p + "'";
  }

  std::string subject() {
    if (in_.ConsumeIntegralInRange(0, 3) == 0)
      return "string.sub(tostring(" + value(1) + "), 1, 24)";
    return pick(kSubjects);
  }

  std::string packFormat() {
    std::string f;
    int n = in_.ConsumeIntegralInRange(1, 4);
    for (int i = 0; i < n; ++i)
      f += pick(kPackItems);
    return "'" + f + "'";
  }

  std::string args(int max) {
    std::string s;
    int n = in_.ConsumeIntegralInRange(0, max);
    for (int i = 0; i < n; ++i)
      s += (i ? ", " : "") + value(1);
    return s;
  }

  /// ", a, b, ..." (zero to max arguments after a first one).
  std::string tailArgs(int max) {
    std::string s;
    int n = in_.ConsumeIntegralInRange(0, max);
    for (int i = 0; i < n; ++i)
      s += ", " + value(1);
    return s;
  }

  // ---- statement families ----------------------------------------------------

  std::string allocation() {
    switch (in_.ConsumeIntegralInRange(0, 11)) {
    case 0:
      return slot() + " = string.rep(" + pick(kRepStrings) + ", " + pick(kSizes) +
             (in_.ConsumeBool() ? std::string(", ") + pick(kStrings) : std::string()) + ")";
    case 1: // array growth
      return "local t = {} for i = 1, " + std::string(pick(kCounts)) + " do t[i] = " +
             pickOf({"i", "i * 0.5", "'s'", "{}", "t", "Vector(i, i, i)", "tostring(i)"}) +
             " end " + slot() + " = t";
    case 2: // hash growth
      return "local t = {} for i = 1, " + std::string(pick(kCounts)) + " do t[" +
             pickOf({"'k' .. i", "i * 0.5", "-i", "{}", "i * 2^40"}) + "] = i end " + slot() +
             " = t";
    case 3: // pieces joined by table.concat
      return "local t = {} for i = 1, " + std::string(pick(kCounts)) +
             " do t[#t + 1] = string.rep(" + pick(kRepStrings) + ", " +
             pickOf({"1", "64", "1024", "i % 100"}) + ") end " + slot() + " = table.concat(t, " +
             pick(kStrings) + ")";
    case 4: // quadratic concatenation, bounded: pieces <= 64 bytes, <= 300 rounds
      return "local s = '' for i = 1, " + pickOf({"10", "100", "300"}) + " do s = s .. " +
             pickOf({"'x'", "i", "string.rep('ab', 32)", "s:sub(1, 10)", "(i % 7) .. ','"}) +
             " end " + slot() + " = s";
    case 5:
      return slot() + " = string.format(" + std::string(pick(kFormats)) + tailArgs(3) + ")";
    case 6:
      return slot() + " = table.concat(" + value() + ", " + pick(kStrings) + ", " + pick(kNumbers) +
             ", " + pick(kNumbers) + ")";
    case 7:
      return slot() + " = {table.unpack(" + pickOf({"{1, 2, 3}", "{}", "v", "{n = 3}"}) + ", " +
             pick(kNumbers) + ", " +
             pickOf({"1", "3", "1e5", "999999", "2^31", "math.maxinteger", "-1", "0/0"}) + ")}";
    case 8: // LRay objects until the limit
      return "for i = 1, " + std::string(pick(kObjectCounts)) + " do " +
             pickOf({"S:add_entity(Sphere())", "v[1] = Vector(i, i, i)", "S:add_light(Light())",
                     "v[2] = Translate(i, 0, 0) * Scale(2)",
                     "v[3] = {Color(1, 1, 1), Texture()}"}) +
             " end";
    case 9: { // a mesh from a generated table
      std::string n = pickOf({"3", "300", "3000", "30000"});
      return "local vs, ix = {}, {} for i = 1, " + n + " do vs[i] = {i, i * 0.5, " +
             pickOf({"0", "0/0", "1e300", "-i"}) + "} end for i = 1, " + n +
             " - 2, 3 do ix[#ix + 1] = {i, i + 1, " + pickOf({"i + 2", "i + 5", "0", "-1"}) +
             "} end " + slot() + " = Mesh { vertices = vs, indices = ix }" +
             (in_.ConsumeBool() ? std::string(" S:add_entity(") + "v[1] or Sphere())" : "");
    }
    case 10:
      return "collectgarbage(" +
             pickOf({"'collect'", "'count'", "'step', 0", "'step', 2^31", "'incremental'",
                     "'generational'", "'stop'", "'restart'", "'isrunning'", "'setpause', 1000",
                     "'bogus'", "'incremental', 1, 1, 1"}) +
             ")";
    default:
      return slot() + " = select(" +
             pickOf({"'#'", "-1", "0", "2^31", "-2^31", "1", "math.mininteger", "'x'"}) +
             tailArgs(3) + ")";
    }
  }

  std::string recursion() {
    switch (in_.ConsumeIntegralInRange(0, 9)) {
    case 0: // plain Lua recursion: Lua stack overflow or the memory limit
      return "local function f(n) if n <= 0 then return 0 end return 1 + f(n - 1) end " + slot() +
             " = f(" + pickOf({"10", "100", "1000", "10000", "50000", "1e7"}) + ")";
    case 1: // tail calls: no stack growth
      return "local function f(n) if n > 0 then return f(n - 1) end return n end " + slot() +
             " = f(" + pickOf({"10", "1000", "30000"}) + ")";
    case 2: // through pcall: C stack
      return "local function f(n) if n > 0 then return pcall(f, n - 1) end error(E_) end " +
             slot() + " = select('#', f(" + pickOf({"10", "150", "199", "200", "250", "10000"}) +
             "))";
    case 3: // xpcall whose handler fails or recurses
      return slot() + " = select(2, xpcall(function() error(" + std::string(pick(kErrorObjects)) +
             ") end, " +
             pickOf({"function(m) error(m) end", "function(m) return m end", "error", "tostring",
                     "nil", "42",
                     "function(m) local function g() return g() + 1 end return g() end",
                     "function(m) return string.rep('x', 2^40) end",
                     "debug and debug.traceback or tostring",
                     "function(m) error(setmetatable({}, {__tostring = function() error('t') "
                     "end})) end"}) +
             "))";
    case 4: { // nested pcall / error levels
      int n = in_.ConsumeIntegralInRange(1, 8);
      std::string s = "error(" + std::string(pick(kErrorObjects)) + ", " +
                      pickOf({"0", "1", "2", "100", "-1", "2^31"}) + ")";
      for (int i = 0; i < n; ++i)
        s = "pcall(function() " + s + " end)";
      return s;
    }
    case 5: // __index / __newindex / __call chains and loops
      return pickOf(
          {"local a = {} for i = 1, " +
               std::string(pickOf({"10", "1999", "2000", "2001", "10000"})) +
               " do a = setmetatable({}, {__index = a}) end v[1] = a.missing",
           "local a, b = {}, {} setmetatable(a, {__index = b}) setmetatable(b, {__index = a}) v[1] "
           "= a.x",
           "local a, b = {}, {} setmetatable(a, {__newindex = b}) setmetatable(b, {__newindex = "
           "a}) a.x = 1",
           "local t = setmetatable({}, {__index = function(t, k) return t[k] end}) v[1] = t.x",
           "local t = setmetatable({}, {__newindex = function(t, k, x) t[k] = x end}) t.x = 1",
           "local c = setmetatable({}, {__call = function(self, n) return 1 + self(n + 1) end}) "
           "c(1)",
           "local c = {} for i = 1, 300 do c = setmetatable({}, {__call = c}) end v[1] = c()",
           "local t = setmetatable({}, {__len = function(t) return #t end}) v[1] = #t",
           "local t = setmetatable({}, {__concat = function(a, b) return a .. b end}) v[1] = t .. "
           "'x'",
           "local t = setmetatable({}, {__eq = function(a, b) return a == b end}) v[1] = t == "
           "setmetatable({}, getmetatable(t))",
           "local t = setmetatable({}, {__tostring = function(t) return tostring(t) end}) v[1] = "
           "tostring(t)",
           "local t = setmetatable({}, {__lt = function(a, b) return a < b end}) v[1] = t < t"});
    case 6: { // deep nesting through load of generated text
      const Nesting &n = kNestings[in_.ConsumeIntegralInRange<size_t>(0, std::size(kNestings) - 1)];
      std::string count = pick(kNestCounts);
      std::string text = "string.rep('" + std::string(n.prefix) + "', " + count + ") .. '" +
                         n.core + "' .. string.rep('" + n.suffix + "', " + count + ")";
      return "local f, e = load(" +
             std::string(pickOf(
                 {"'return ' .. ", "'local a, b, f, x; return ' .. ", "''.. ", "'x = ' .. "})) +
             text + ") " + slot() + " = e if f then " + slot() + " = f() end";
    }
    case 7: // to-be-closed variables
      return "local x <close> = " +
             pickOf({"setmetatable({}, {__close = function(o, e) " +
                         std::string(pick(kCloseBodies)) + " end})",
                     "42", "nil", "false", "{}", "setmetatable({}, {__close = 1})",
                     "setmetatable({}, {__close = function(o, e) local y <close> = o end})"}) +
             " " + pick(kCloseBodies);
    case 8: // a reader function for load
      return "local n = 0 local f, e = load(function() n = n + 1 if n <= " +
             pickOf({"1", "10", "100"}) + " then return " +
             pickOf({"'x'", "string.rep('y', 1024)", "'return 1 '", "1", "{}", "''", "'--'",
                     "'\\27Lua'", "error(E_)"}) +
             " end end) " + slot() + " = e";
    default: // mutual recursion through string.gsub callbacks (C -> Lua -> C)
      return "local function f(s) return (string.gsub(s, '.', f)) end " + slot() + " = f('ab')";
    }
  }

  std::string libraryCall() {
    switch (in_.ConsumeIntegralInRange(0, 13)) {
    case 0:
      return slot() + " = {string." + pickOf({"find", "match"}) + "(" + subject() + ", " +
             pattern() +
             (in_.ConsumeBool() ? ", " +
                                      std::string(pickOf({"1", "-1", "0", "100", "math.mininteger",
                                                          "math.maxinteger", "1.5", "-100"})) +
                                      (in_.ConsumeBool() ? ", true" : "")
                                : std::string()) +
             ")}";
    case 1:
      return slot() + " = {string.gsub(" + subject() + ", " + pattern() + ", " +
             pickOf({"'%0%0'", "'%1'", "'%2'", "'%'", "'%9'", "'x'", "{a = 'A', b = false}",
                     "function(...) return ... end", "function() return {} end",
                     "function() error(E_) end",
                     "setmetatable({}, {__index = function() return 'i' end})", "42", "nil",
                     "string.rep('r', 4096)"}) +
             (in_.ConsumeBool()
                  ? ", " + std::string(pickOf({"0", "1", "-1", "math.maxinteger", "0/0", "1.5"}))
                  : std::string()) +
             ")}";
    case 2:
      return "local n = 0 for a, b in string.gmatch(" + subject() + ", " + pattern() +
             (in_.ConsumeBool() ? ", " + std::string(pickOf({"1", "-1", "100", "math.mininteger"}))
                                : std::string()) +
             ") do n = n + 1 if n > 1000 then break end end " + slot() + " = n";
    case 3:
      return slot() + " = {string." + pickOf({"byte", "sub"}) + "(" + value() + ", " +
             pick(kNumbers) + ", " + pick(kNumbers) + ")}";
    case 4:
      return slot() + " = string.char(" + args(4) + ")";
    case 5:
      return slot() + " = {string." + pickOf({"pack", "unpack", "packsize"}) + "(" + packFormat() +
             tailArgs(3) + ")}";
    case 6:
      return slot() + " = {string." + pickOf({"len", "upper", "lower", "reverse", "dump"}) + "(" +
             value() + ")}";
    case 7:
      return slot() + " = {utf8." + pickOf({"char", "codepoint", "len", "offset"}) + "(" + args(4) +
             ")}";
    case 8:
      return "local n = 0 for p, c in utf8.codes(" + subject() +
             (in_.ConsumeBool() ? ", true" : "") + ") do n = n + 1 end " + slot() + " = n";
    case 9: { // table functions on a fresh, bounded table
      // (Not with a __len of 2^40 for insert and remove: they would move
      // 2^40 elements in one C call, past the watchdog.)
      bool shifts = in_.ConsumeBool();
      std::string t = pickOf({"{}", "{3, 1, 2}", "{1, 'x', {}}", "{0/0, 1, 0/0, 2}",
                              shifts ? "setmetatable({}, {__len = function() return 2^16 end})"
                                     : "setmetatable({}, {__len = function() return 2^40 end})",
                              "setmetatable({}, {__len = function() return 1e4 end})",
                              "setmetatable({}, {__len = function() return 0.5 end})",
                              "setmetatable({1, 2}, {__index = function(t, k) return k end, "
                              "__newindex = function() error(E_) end})"});
      std::string n = pickOf({"1", "3", "100", "2000"});
      return "local t = " + t + " for i = 1, " + n + " do rawset(t, i, (i * 7919) % 1000) end " +
             (shifts
                  ? pickOf({"table.insert(t, " + pick(kNumbers) + ", 1)",
                            "table.insert(t, 1, 2, 3)", "table.remove(t, " + pick(kNumbers) + ")",
                            "table.remove(t)", "table.insert(t, 'x')"})
                  : pickOf(
                        {"table.sort(t, " +
                             std::string(pickOf(
                                 {"function(a, b) return true end",
                                  "function(a, b) return a > b end", "function(a, b) error(E_) end",
                                  "function(a, b) return nil end",
                                  "function(a, b) return a < b end", "nil", "42",
                                  "function(a, b) t[#t + 1] = 1 return a < b end"})) +
                             ")",
                         "table.move(t, " +
                             std::string(pickOf({"1, 3, 2", "1, 1000, 500",
                                                 "math.mininteger, -1, 1", "-5, 5, 1", "1, 0, 1",
                                                 "2, 1, math.maxinteger", "1, 3, math.maxinteger",
                                                 "1, 3, math.mininteger", "0/0, 1, 1"})) +
                             ")",
                         slot() + " = table.concat(t, ',', " +
                             std::string(pickOf(
                                 {"1, #t", "1, 10", "0, 1", "1, math.maxinteger", "-3, 3"})) +
                             ")",
                         slot() + " = select('#', table.unpack(t))",
                         slot() + " = table.pack(table.unpack(t, 1, 100))"}));
    }
    case 10:
      return slot() + " = " +
             pickOf(
                 {"math.floor", "math.ceil",  "math.abs",     "math.tointeger", "math.type",
                  "math.sqrt",  "math.log",   "math.exp",     "math.fmod",      "math.modf",
                  "math.max",   "math.min",   "math.ult",     "math.random",    "math.randomseed",
                  "math.atan",  "tostring",   "tonumber",     "type",           "rawlen",
                  "rawequal",   "rawget",     "rawset",       "next",           "ipairs",
                  "pairs",      "select",     "getmetatable", "setmetatable",   "assert",
                  "unpack",     "string.len", "utf8.char",    "error"}) +
             "(" + args(3) + ")";
    case 11:
      return slot() + " = tonumber(" + pick(kStrings) + ", " +
             pickOf({"2", "10", "16", "36", "1", "37", "0", "nil", "0/0", "2^63"}) + ")";
    case 12: // operators on odd values
      return slot() + " = " + value() +
             pickOf({" + ", " // ", " % ", " << ", " >> ", " & ", " ^ ", " .. ", " < ",
                     " == ", " / "}) +
             value();
    default: // iteration on odd values, bounded
      return "local n = 0 for k, x in " + pickOf({"pairs", "ipairs", "next,"}) + "(" + value() +
             ") do n = n + 1 if n > 100 then break end end " + slot() + " = n";
    }
  }

  /// Files and the io/os wrappers; must_fail_ records an escape.
  std::string sandboxProbe() {
    switch (in_.ConsumeIntegralInRange(0, 9)) {
    case 0:
    case 1: {
      std::string path = pick(kOutsidePaths), f = pickOf({"io.open", "io.lines"});
      return "must_fail_('" + f + " ' .. tostring(" + path + "), " + f + ", " + path +
             (in_.ConsumeBool() ? std::string(", ") + pickOf({"'r'", "'rb'", "nil", "'l'"})
                                : std::string()) +
             ")";
    }
    case 2:
      return "must_fail_('write mode', io.open, " + std::string(pick(kInsidePaths)) + ", " +
             pickOf({"'w'", "'a'", "'r+'", "'w+'", "'rw'", "'x'", "'rb+'", "''", "'r\\0w'", "'wb'",
                     "'a+'"}) +
             ")";
    case 3:
      return slot() + " = {pcall(" +
             pickOf({"dofile", "loadfile", "mesh_from_obj", "ImagePigment2D", "io.lines", "require",
                     "io.open"}) +
             ", " + (in_.ConsumeBool() ? pick(kOutsidePaths) : pick(kInsidePaths)) + ")}";
    case 4: // reading an inside file
      return "local f = io.open(" + std::string(pick(kInsidePaths)) + ", " +
             pickOf({"'r'", "'rb'", "nil"}) + ") if f then " +
             pickOf({slot() + " = {f:read(" + std::string(pick(kReadFormats)) + ", " +
                         pick(kReadFormats) + ")}",
                     slot() + " = {f:seek(" +
                         std::string(pickOf(
                             {"'set', 2^62", "'end', -100", "'bad'", "'cur', 0/0", "'set', -1"})) +
                         ")}",
                     slot() + " = {f:write('x')}", "f:close() f:close()", "f:setvbuf('no')",
                     "local n = 0 for l in f:lines(" + std::string(pick(kReadFormats)) +
                         ") do n = n + 1 if n > 100 then break end end",
                     slot() + " = f", slot() + " = tostring(f)",
                     "f:close() " + slot() + " = {f:read('a')}"}) +
             " end";
    case 5:
      return "local n = 0 for a, b in io.lines(" + std::string(pick(kInsidePaths)) + ", " +
             pick(kReadFormats) +
             (in_.ConsumeBool() ? std::string(", ") + pick(kReadFormats) : std::string()) +
             ") do n = n + 1 if n > 100 then break end end";
    case 6:
      return slot() + " = {os.date(" + std::string(pick(kDateFormats)) + ", " + pick(kTimes) + ")}";
    case 7:
      return slot() + " = {os.time(" +
             pickOf({"", "{}", "{year = 2^31, month = 1, day = 1}",
                     "{year = 2000, month = 2^40, day = 1}",
                     "{year = 2000, month = 1, day = 1, hour = 0/0}",
                     "{year = -2^31, month = 1, day = 1}", "{year = 'x', month = 1, day = 1}",
                     "{year = 2000, month = 1, day = 1, isdst = {}}", "42",
                     "{day = math.mininteger, month = 1, year = 1}"}) +
             ")} " + slot() + " = os.clock()";
    case 8: // binary chunks stay refused, __gc stays refused
      return pickOf(
          {"must_fail_('binary chunk', load, string.dump(function() return 1 end), 'b', 'b')",
           "must_fail_('binary chunk', load, string.dump(function() return 1 end))",
           "must_fail_('binary file', loadfile, 'binary.lua', 'b')",
           "must_fail_('__gc', setmetatable, {}, {__gc = function() end})",
           "must_fail_('__gc', setmetatable, {}, {__gc = true})",
           "do local t = setmetatable({}, setmetatable({}, {__index = {__gc = function() escaped_ "
           "= '__gc ran' end}})) end collectgarbage() collectgarbage()",
           "must_fail_('userdata metatable', getmetatable, S)",
           "must_fail_('file metatable', getmetatable, io.open('data.txt'))",
           "must_fail_('stdin', loadfile)", "must_fail_('stdin', io.lines)",
           "getmetatable('').__index = " + value(),
           "getmetatable('').__gc = function() escaped_ = 'string __gc' end",
           "getmetatable('').__add = " + value()});
    default: // load with odd text, names, modes and environments
      return "local f, e = load(" + std::string(pick(kChunks)) + ", " +
             pickOf({"nil", "'=x'", "'@/etc/passwd'", "string.rep('n', 10000)", "42", "{}"}) +
             ", " + pickOf({"'t'", "'b'", "'bt'", "nil", "'x'", "''"}) + ", " +
             pickOf({"nil", "{}", "_G", "{x = 1}", "42"}) + ") " + slot() + " = e if f then " +
             slot() + " = {pcall(f" + tailArgs(2) + ")} end";
    }
  }

  std::string statement() {
    switch (in_.ConsumeIntegralInRange(0, 11)) {
    case 0:
    case 1:
    case 2:
      return allocation();
    case 3:
    case 4:
      return recursion();
    case 5:
    case 6:
    case 7:
      return libraryCall();
    case 8:
    case 9:
      return sandboxProbe();
    case 10:
      return "E_ = " + std::string(pick(kErrorObjects));
    default: // operations on an object with a random metatable
      return "local o = " + metaObject(0) + " " +
             pickOf({slot() + " = o.x",
                     "o.x = 1",
                     slot() + " = o()",
                     slot() + " = #o",
                     slot() + " = o .. 'x'",
                     slot() + " = o + 1",
                     slot() + " = o == {}",
                     slot() + " = o < o",
                     slot() + " = -o",
                     slot() + " = tostring(o)",
                     "for k in pairs(o) do end",
                     "for i in ipairs(o) do if i > 100 then break end end",
                     "o[nil] = 1",
                     slot() + " = o // 0",
                     slot() + " = ~o",
                     "local c <close> = o",
                     "setmetatable(o, {})",
                     slot() + " = getmetatable(o)",
                     slot() + " = rawlen(o)",
                     "error(o)",
                     slot() + " = o"});
    }
  }

  /// The end of scene(clock).
  std::string sceneReturn() {
    switch (in_.ConsumeIntegralInRange(0, 9)) {
    case 0:
      return "return nil";
    case 1:
      return "return " + value();
    case 2:
      return "error(" + std::string(pick(kErrorObjects)) + ")";
    case 3:
      return "return Scene()";
    case 4:
      return "return S, 1, 2";
    case 5:
      return "local function r(n) return 1 + r(n + 1) end return r(1)"; // stack overflow in
                                                                        // buildFrame
    default:
      return "return S";
    }
  }

  std::string errorObject() { return pick(kErrorObjects); }

private:
  template <size_t N> std::string pick(const char *const (&list)[N]) {
    return list[in_.ConsumeIntegralInRange<size_t>(0, N - 1)];
  }
  std::string pickOf(std::initializer_list<std::string> list) {
    return *(list.begin() + in_.ConsumeIntegralInRange<size_t>(0, list.size() - 1));
  }
  FuzzedDataProvider &in_;
};

/// Run first: locals the fuzzed statements cannot reach through _G, and
/// the checks that forbidden libraries are absent.
std::string header() {
  return "local base_ = '" + gBaseDir +
         "'\n"
         "local pcall_, type_, escaped_ = pcall, type, nil\n"
         "local function must_fail_(what, f, ...)\n"
         "  local ok, r = pcall_(f, ...)\n"
         "  if ok and r ~= nil and r ~= false then\n"
         "    escaped_ = escaped_ or what\n"
         "    if type_(r) == 'userdata' then pcall_(function() r:close() end) end\n"
         "  end\n"
         "end\n"
         "for _, n in ipairs({'coroutine', 'debug', 'package', 'require'}) do\n"
         "  if rawget(_G, n) ~= nil then escaped_ = escaped_ or n end\n"
         "end\n"
         "for _, n in ipairs({'execute', 'exit', 'remove', 'rename', 'getenv', 'tmpname', "
         "'setlocale'}) do\n"
         "  if rawget(os, n) ~= nil then escaped_ = escaped_ or ('os.' .. n) end\n"
         "end\n"
         "for _, n in ipairs({'popen', 'write', 'read', 'output', 'input', 'stdout', 'stderr', "
         "'stdin', 'tmpfile', 'close'}) do\n"
         "  if rawget(io, n) ~= nil then escaped_ = escaped_ or ('io.' .. n) end\n"
         "end\n"
         "local v = {}\n"
         "local S = Scene()\n"
         "E_ = 'e'\n";
}

const char kCheck[] = "if escaped_ then error('SANDBOX_ESCAPE: ' .. escaped_, 0) end\n";

/// The script's memory limit, drawn with these weights: mostly 1 MiB, so
/// that huge requests are refused before any page is touched and a loop
/// that grows a table, the Lua stack or a buffer meets the limit within a
/// few milliseconds (a fuzzer spends most of its time in the slowest
/// inputs); 4, 16 and 64 MiB, more rarely, for big strings and the real
/// Lua stack overflow; 160 to 256 KiB makes the limit bite in the bindings'
/// own allocations and in finalizer calls; 32 KiB is below what LRay's
/// libraries take (a clean error, once an abort).
uint64_t memoryLimit(FuzzedDataProvider &in) {
  constexpr uint64_t kKiB = 1024, kMiB = kKiB << 10;
  const int draw = in.ConsumeIntegralInRange(0, 99);
  if (draw < 1) return 64 * kMiB;
  if (draw < 3) return 16 * kMiB;
  if (draw < 10) return 4 * kMiB;
  if (draw < 11) return 32 * kKiB;
  if (draw < 25) return (160 + 16 * in.ConsumeIntegralInRange(0, 6)) * kKiB;
  return 1 * kMiB;
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int *, char ***) {
  makeBaseDir();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  FuzzedDataProvider in(data, size);
  Writer w(in);
  lray::ScriptOptions options;
  options.memoryLimitBytes = memoryLimit(in);
  options.timeoutSeconds = 0.25;
  std::string source = header();
  source += "local P_ = pcall\n";
  for (int i = 0; i < 8 && in.remaining_bytes() > 0; ++i)
    source += "P_(function() " + w.statement() + " end)\n";
  source += kCheck;
  int ending = in.ConsumeIntegralInRange(0, 7);
  if (ending == 0)
    source += "error(" + w.errorObject() + ")\n"; // the message handler on odd objects
  if (ending != 1) {
    source += "function scene(clock)\n";
    for (int i = 0; i < 3 && in.remaining_bytes() > 0 && in.ConsumeBool(); ++i)
      source += "  P_(function() " + w.statement() + " end)\n";
    source += std::string("  ") + kCheck + "  " + w.sceneReturn() + "\nend\n";
  }
  // SCRIPT_FUZZ_PRINT=1 shows each script, its limit and its outcome (for minimising).
  if (std::getenv("SCRIPT_FUZZ_PRINT"))
    std::fprintf(stderr, "---- script (memory limit %llu bytes) ----\n%s\n",
                 static_cast<unsigned long long>(options.memoryLimitBytes), source.c_str());
  try {
    lray::SceneScript script = lray::SceneScript::fromString(source, "fuzz.lua", gBaseDir, options);
    lray::Scene scene = script.buildFrame(script.info().startClock);
    (void)scene;
  } catch (const lray::SceneError &e) {
    // A clear user error: fine, unless the script reported a sandbox escape.
    if (std::strstr(e.what(), "SANDBOX_ESCAPE")) {
      std::fprintf(stderr, "script_fuzz: sandbox escape: %s\n", e.what());
      std::abort();
    }
    if (std::getenv("SCRIPT_FUZZ_PRINT")) std::fprintf(stderr, "SceneError: %s\n", e.what());
  } catch (const std::exception &e) {
    std::fprintf(stderr, "script_fuzz: an exception other than SceneError: %s\n", e.what());
    std::abort();
  }
  return 0;
}
