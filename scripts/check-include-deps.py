#!/usr/bin/env python3
"""Fails when a C++ file includes a header of a folder that its CMake target does not link.

Every folder is one target (CMakeLists.txt: candela_folder(NAME FOLDERS ... DEPENDS ...)), and a
target may include the headers of the targets it links, directly or through their PUBLIC and
INTERFACE dependencies, and nothing else: an include that crosses to another folder without the
dependency compiles today only because some other target happens to bring the include path, and
breaks the day the graph changes (issue 28).

Nothing about the graph is written here. The script reads CMakeLists.txt and the files it
add_subdirectory()s with a small CMake interpreter (set, list, option, file(GLOB), if, foreach,
function with cmake_parse_arguments, add_library, add_executable, target_link_libraries,
target_sources, target_include_directories, add_dependencies, configure_file, file(GENERATE),
file(CONFIGURE), ...; commands it does not know are skipped). Every option() is taken as ON and
BUILD_TESTING as ON, so that optional targets (tests, fuzzers) are checked too; -D VAR=VALUE
overrides that.

Then:
  * a folder belongs to the targets that compile its .cpp files (a file(GLOB_RECURSE) owns the
    subfolders too; a folder named in a glob owns it even when it holds only headers), and a header
    listed in a target's sources (target_sources, e.g. of an INTERFACE library for header-only code)
    belongs to that target as well;
  * every .cpp and .h of a target's folders is scanned for #include "x/..." (and <x/...> when x is a
    folder of the repository or a generated header); the files that include it are checked against
    the targets that compile them, a header against the targets that own its folder;
  * an include is fine when the including target is, or transitively links, a target that owns the
    included file; otherwise it is a violation. An include of a folder that no target owns is a
    violation too. A header that CMake generates (configure_file, file(GENERATE), file(CONFIGURE)
    into a directory that some target puts on its include path, e.g. <candela/version.h>) is fine
    when the including target has that include directory, its own or through what it links.

Output: one line per violation (path:line: ...) and exit status 1, or a one-line summary and 0.
Run from anywhere: python3 scripts/check-include-deps.py [--source-dir DIR]. The script's own
tests: python3 scripts/check-include-deps.py --self-test.
"""

from __future__ import annotations

import argparse
import fnmatch
import os
import re
import sys
from dataclasses import dataclass, field

# The binary directory does not exist while checking: generated files are recorded under this name.
BINARY_DIR = "/@CMAKE_BINARY_DIR@"
CXX_SOURCE_EXTENSIONS = {".cpp", ".cc", ".cxx", ".c++", ".c"}
CXX_HEADER_EXTENSIONS = {".h", ".hh", ".hpp", ".hxx", ".inl", ".ipp", ".tpp"}
CXX_EXTENSIONS = CXX_SOURCE_EXTENSIONS | CXX_HEADER_EXTENSIONS


class CMakeError(Exception):
    pass


# ----------------------------------------------------------------------------------------------
# CMake lexer: the file as a list of command invocations with their raw arguments.


@dataclass
class Arg:
    text: str
    kind: str  # "unquoted", "quoted" or "bracket"


@dataclass
class Command:
    name: str  # lower case
    args: list[Arg]
    path: str
    line: int


_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_BRACKET_OPEN = re.compile(r"\[(=*)\[")


def parse_cmake(text: str, path: str) -> list[Command]:
    commands: list[Command] = []
    i, n, line = 0, len(text), 1

    def skip_bracket(start: int) -> tuple[str, int]:
        """text[start:] opens a bracket ([==[); returns its content and the index after it."""
        m = _BRACKET_OPEN.match(text, start)
        close = "]" + m.group(1) + "]"
        end = text.find(close, m.end())
        if end < 0:
            raise CMakeError(f"{path}:{line}: unterminated bracket")
        content = text[m.end():end]
        if content.startswith("\r\n"):
            content = content[2:]
        elif content.startswith("\n"):
            content = content[1:]
        return content, end + len(close)

    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
        elif c.isspace():
            i += 1
        elif c == "#":
            if _BRACKET_OPEN.match(text, i + 1):
                _, j = skip_bracket(i + 1)
            else:
                j = text.find("\n", i)
                j = n if j < 0 else j
            line += text.count("\n", i, j)
            i = j
        else:
            m = _IDENT.match(text, i)
            if not m:
                raise CMakeError(f"{path}:{line}: unexpected {text[i]!r}")
            name, cmd_line = m.group(0).lower(), line
            i = m.end()
            while i < n and text[i] in " \t":
                i += 1
            if i >= n or text[i] != "(":
                raise CMakeError(f"{path}:{line}: expected ( after {name}")
            i += 1
            args: list[Arg] = []
            depth = 0
            while True:
                if i >= n:
                    raise CMakeError(f"{path}:{cmd_line}: unterminated {name}(")
                c = text[i]
                if c == "\n":
                    line += 1
                    i += 1
                elif c.isspace():
                    i += 1
                elif c == "#":
                    if _BRACKET_OPEN.match(text, i + 1):
                        _, j = skip_bracket(i + 1)
                    else:
                        j = text.find("\n", i)
                        j = n if j < 0 else j
                    line += text.count("\n", i, j)
                    i = j
                elif c == "(":
                    depth += 1
                    args.append(Arg("(", "unquoted"))
                    i += 1
                elif c == ")":
                    if depth == 0:
                        i += 1
                        break
                    depth -= 1
                    args.append(Arg(")", "unquoted"))
                    i += 1
                elif c == '"':
                    j = i + 1
                    while j < n and text[j] != '"':
                        j += 2 if text[j] == "\\" else 1
                    if j >= n:
                        raise CMakeError(f"{path}:{line}: unterminated string")
                    raw = text[i + 1:j]
                    line += raw.count("\n")
                    # A backslash before a newline continues the line: no newline in the value.
                    args.append(Arg(re.sub(r"\\\r?\n", "", raw), "quoted"))
                    i = j + 1
                elif c == "[" and _BRACKET_OPEN.match(text, i):
                    content, j = skip_bracket(i)
                    line += text.count("\n", i, j)
                    args.append(Arg(content, "bracket"))
                    i = j
                else:
                    j = i
                    while j < n:
                        d = text[j]
                        if d == "\\":
                            j += 2
                        elif d.isspace() or d in "()#":
                            break
                        elif d == '"':  # legacy unquoted argument: a"b c"d is one argument
                            k = text.find('"', j + 1)
                            j = n if k < 0 else k + 1
                        else:
                            j += 1
                    args.append(Arg(text[i:j], "unquoted"))
                    i = j
            commands.append(Command(name, args, path, cmd_line))
    return commands


# ----------------------------------------------------------------------------------------------
# Interpreter


TRUE_CONSTANTS = {"1", "ON", "YES", "TRUE", "Y"}
FALSE_CONSTANTS = {"0", "OFF", "NO", "FALSE", "N", "IGNORE", "NOTFOUND", ""}


def is_false_constant(value: str) -> bool:
    return value.upper() in FALSE_CONSTANTS or value.upper().endswith("-NOTFOUND")


def is_true_constant(value: str) -> bool:
    if value.upper() in TRUE_CONSTANTS:
        return True
    try:
        return float(value) != 0
    except ValueError:
        return False


def split_list(value: str) -> list[str]:
    """A CMake list's elements (';' separated, '\\;' kept), empty elements dropped."""
    items, current, i = [], [], 0
    depth = 0  # ';' inside [] is not a separator in CMake lists
    while i < len(value):
        c = value[i]
        if c == "\\" and i + 1 < len(value) and value[i + 1] == ";":
            current.append(";")
            i += 2
            continue
        if c == "[":
            depth += 1
        elif c == "]" and depth:
            depth -= 1
        if c == ";" and depth == 0:
            items.append("".join(current))
            current = []
        else:
            current.append(c)
        i += 1
    items.append("".join(current))
    return [item for item in items if item != ""]


@dataclass
class Target:
    name: str
    kind: str  # OBJECT, STATIC, SHARED, MODULE, INTERFACE, UNKNOWN (add_library), EXECUTABLE, IMPORTED
    path: str  # the CMakeLists.txt defining it
    line: int
    source_dir: str  # CMAKE_CURRENT_SOURCE_DIR where it was defined
    sources: set[str] = field(default_factory=set)  # absolute paths
    owned_dirs: dict[str, bool] = field(default_factory=dict)  # absolute dir -> recursive
    links: list[tuple[str, str]] = field(default_factory=list)  # (PUBLIC|PRIVATE|INTERFACE, name)
    include_dirs: list[tuple[str, str]] = field(default_factory=list)  # (scope, absolute dir)
    build_deps: list[str] = field(default_factory=list)  # add_dependencies
    # The function call (outermost) that created the target, when a function did, and whether
    # that call takes a DEPENDS list: then a missing dependency goes there.
    via_function: str | None = None
    via_function_depends: bool = False


class Return(Exception):
    pass


class Break(Exception):
    pass


@dataclass
class Function:
    name: str
    params: list[str]
    body: list[Command]
    is_macro: bool


class Interpreter:
    def __init__(self, source_dir: str, defines: dict[str, str]):
        self.root = os.path.abspath(source_dir)
        self.defines = defines
        self.targets: dict[str, Target] = {}
        self.aliases: dict[str, str] = {}
        self.functions: dict[str, Function] = {}
        self.generated: set[str] = set()  # absolute paths of files CMake writes
        # Per scope (id of its variables) and variable: the file(GLOB)s whose result it holds, as
        # (the glob's base directory, recursive). A target whose sources name the variable owns
        # those folders (their subfolders too for GLOB_RECURSE), even folders with only headers.
        self.glob_vars: dict[int, dict[str, list[tuple[str, bool]]]] = {}
        self.call_stack: list[tuple[Function, Command]] = []
        self._parents: list[dict[str, str]] = []  # the calling scopes, for set(... PARENT_SCOPE)
        self.listfiles: list[str] = []

    # -- variables ------------------------------------------------------------------------------

    def expand(self, text: str, vars: dict[str, str], refs: list[str] | None = None) -> str:
        """Variable references ${X}, $ENV{X} and escapes of one argument."""
        out: list[str] = []
        i, n = 0, len(text)
        while i < n:
            c = text[i]
            if c == "\\" and i + 1 < n:
                e = text[i + 1]
                out.append({"n": "\n", "t": "\t", "r": "\r", "0": "\0"}.get(e, "\\;" if e == ";" else e))
                i += 2
            elif c == "$" and (m := re.match(r"\$(ENV|CACHE)?\{", text[i:])):
                # Find the matching brace (references nest: ${a_${b}}).
                depth, j = 1, i + m.end()
                while j < n and depth:
                    if text[j] == "{":
                        depth += 1
                    elif text[j] == "}":
                        depth -= 1
                    j += 1
                inner = self.expand(text[i + m.end():j - 1], vars, refs)
                if m.group(1) == "ENV":
                    out.append(os.environ.get(inner, ""))
                else:
                    if refs is not None:
                        refs.append(inner)
                    out.append(vars.get(inner, ""))
                i = j
            else:
                out.append(c)
                i += 1
        return "".join(out)

    def expand_args(self, args: list[Arg], vars: dict[str, str], refs: list[str] | None = None,
                    keep_quoted: bool = False) -> list:
        """The argument list as CMake passes it to a command: unquoted arguments split into list
        elements. With keep_quoted, (value, quoted) pairs (for if())."""
        result = []
        for arg in args:
            if arg.kind == "bracket":
                result.append((arg.text, True) if keep_quoted else arg.text)
            elif arg.kind == "quoted":
                value = self.expand(arg.text, vars, refs).replace("\\;", ";")
                result.append((value, True) if keep_quoted else value)
            else:
                value = self.expand(arg.text, vars, refs)
                for item in split_list(value):
                    result.append((item, False) if keep_quoted else item)
        return result

    # -- execution ------------------------------------------------------------------------------

    def run_file(self, path: str, vars: dict[str, str]) -> None:
        self.listfiles.append(path)
        with open(path, encoding="utf-8") as f:
            commands = parse_cmake(f.read(), path)
        try:
            self.run(commands, vars)
        except Return:
            pass

    @staticmethod
    def _block_end(commands: list[Command], start: int, opener: str, closer: str,
                   middles: tuple[str, ...] = ()) -> tuple[int, list[int]]:
        """Index of the command closing the block opened at start, and of its middle commands
        (elseif/else) at the same depth."""
        depth, middle = 0, []
        for k in range(start, len(commands)):
            name = commands[k].name
            if name == opener:
                depth += 1
            elif name == closer:
                depth -= 1
                if depth == 0:
                    return k, middle
            elif depth == 1 and name in middles:
                middle.append(k)
        raise CMakeError(f"{commands[start].path}:{commands[start].line}: {opener} without {closer}")

    def run(self, commands: list[Command], vars: dict[str, str]) -> None:
        i = 0
        while i < len(commands):
            cmd = commands[i]
            if cmd.name == "if":
                end, middles = self._block_end(commands, i, "if", "endif", ("elseif", "else"))
                bounds = [i] + middles + [end]
                for b in range(len(bounds) - 1):
                    head = commands[bounds[b]]
                    if head.name == "else" or self.condition(head, vars):
                        self.run(commands[bounds[b] + 1:bounds[b + 1]], vars)
                        break
                i = end + 1
            elif cmd.name == "foreach":
                end, _ = self._block_end(commands, i, "foreach", "endforeach")
                self.foreach(cmd, commands[i + 1:end], vars)
                i = end + 1
            elif cmd.name == "while":
                end, _ = self._block_end(commands, i, "while", "endwhile")
                guard = 0
                try:
                    while self.condition(cmd, vars) and guard < 10000:
                        self.run(commands[i + 1:end], vars)
                        guard += 1
                except Break:
                    pass
                i = end + 1
            elif cmd.name in ("function", "macro"):
                closer = "end" + cmd.name
                end, _ = self._block_end(commands, i, cmd.name, closer)
                args = self.expand_args(cmd.args, vars)
                self.functions[args[0].lower()] = Function(args[0], args[1:], commands[i + 1:end],
                                                           cmd.name == "macro")
                i = end + 1
            elif cmd.name == "break":
                raise Break()
            elif cmd.name == "return":
                raise Return()
            else:
                self.command(cmd, vars)
                i += 1

    def foreach(self, cmd: Command, body: list[Command], vars: dict[str, str]) -> None:
        args = self.expand_args(cmd.args, vars)
        if not args:
            return
        var, rest = args[0], args[1:]
        if rest[:1] == ["RANGE"]:
            nums = [int(x) for x in rest[1:]]
            start, stop, step = (0, nums[0], 1) if len(nums) == 1 else (nums + [1])[:3]
            items = [str(x) for x in range(start, stop + 1, step)]
        elif rest[:1] == ["IN"]:
            items, mode = [], None
            for word in rest[1:]:
                if word in ("LISTS", "ITEMS", "ZIP_LISTS"):
                    mode = word
                elif mode == "LISTS":
                    items.extend(split_list(vars.get(word, "")))
                else:
                    items.append(word)
        else:
            items = rest
        saved = vars.get(var)
        try:
            for item in items:
                vars[var] = item
                self.run(body, vars)
        except Break:
            pass
        if saved is None:
            vars.pop(var, None)
        else:
            vars[var] = saved

    # -- if() conditions ------------------------------------------------------------------------

    def condition(self, cmd: Command, vars: dict[str, str]) -> bool:
        tokens = self.expand_args(cmd.args, vars, keep_quoted=True)
        pos = 0

        def value(tok):
            text, quoted = tok
            if not quoted and text in vars:
                return vars[text]
            return text

        def truth(tok) -> bool:
            text, quoted = tok
            if is_true_constant(text):
                return True
            if is_false_constant(text):
                return False
            if quoted:
                return False
            return text in vars and not is_false_constant(vars[text])

        unary = {"DEFINED", "TARGET", "EXISTS", "COMMAND", "POLICY", "IS_DIRECTORY", "IS_ABSOLUTE",
                 "IS_SYMLINK", "TEST"}
        binary = {"STREQUAL", "EQUAL", "LESS", "GREATER", "LESS_EQUAL", "GREATER_EQUAL", "STRLESS",
                  "STRGREATER", "STRLESS_EQUAL", "STRGREATER_EQUAL", "MATCHES", "VERSION_LESS",
                  "VERSION_GREATER", "VERSION_EQUAL", "VERSION_LESS_EQUAL", "VERSION_GREATER_EQUAL",
                  "IN_LIST", "IS_NEWER_THAN", "PATH_EQUAL"}

        def peek():
            return tokens[pos] if pos < len(tokens) else None

        def is_kw(tok, words) -> bool:
            return tok is not None and not tok[1] and tok[0] in words

        def version(v: str):
            return [int(x) if x.isdigit() else 0 for x in re.split(r"[.]", v)]

        def primary() -> bool:
            nonlocal pos
            tok = peek()
            if tok is None:
                return False
            if is_kw(tok, {"("}):
                pos += 1
                result = or_expr()
                if is_kw(peek(), {")"}):
                    pos += 1
                return result
            if is_kw(tok, unary) and pos + 1 < len(tokens):
                op, arg = tok[0], tokens[pos + 1][0]
                pos += 2
                if op == "DEFINED":
                    m = re.fullmatch(r"(ENV|CACHE)\{(.*)\}", arg)
                    return (m.group(2) in os.environ) if m and m.group(1) == "ENV" else \
                        ((m.group(2) if m else arg) in vars)
                if op == "TARGET":
                    return arg in self.targets or arg in self.aliases
                if op == "COMMAND":
                    return arg.lower() in self.functions
                if op in ("EXISTS", "IS_DIRECTORY"):
                    return os.path.isdir(arg) if op == "IS_DIRECTORY" else os.path.exists(arg)
                if op == "IS_ABSOLUTE":
                    return os.path.isabs(arg)
                return False
            pos += 1
            nxt = peek()
            if is_kw(nxt, binary) and pos + 1 < len(tokens):
                op, rhs_tok = nxt[0], tokens[pos + 1]
                pos += 2
                lhs, rhs = value(tok), value(rhs_tok)
                if op == "STREQUAL":
                    return lhs == rhs
                if op == "MATCHES":
                    m = re.search(rhs, lhs)
                    if m:
                        for k in range(10):
                            vars[f"CMAKE_MATCH_{k}"] = (m.group(k) or "") if k <= (m.re.groups or 0) else ""
                    return m is not None
                if op == "IN_LIST":
                    return lhs in split_list(vars.get(rhs_tok[0], ""))
                if op.startswith("VERSION_"):
                    a, b = version(lhs), version(rhs)
                    width = max(len(a), len(b))
                    a, b = a + [0] * (width - len(a)), b + [0] * (width - len(b))
                    return {"VERSION_LESS": a < b, "VERSION_GREATER": a > b, "VERSION_EQUAL": a == b,
                            "VERSION_LESS_EQUAL": a <= b, "VERSION_GREATER_EQUAL": a >= b}[op]
                if op.startswith("STR"):
                    return {"STRLESS": lhs < rhs, "STRGREATER": lhs > rhs, "STRLESS_EQUAL": lhs <= rhs,
                            "STRGREATER_EQUAL": lhs >= rhs}[op]
                if op == "PATH_EQUAL":
                    return os.path.normpath(lhs) == os.path.normpath(rhs)
                try:
                    x, y = float(lhs), float(rhs)
                except ValueError:
                    return False
                return {"EQUAL": x == y, "LESS": x < y, "GREATER": x > y, "LESS_EQUAL": x <= y,
                        "GREATER_EQUAL": x >= y}.get(op, False)
            return truth(tok)

        def not_expr() -> bool:
            nonlocal pos
            if is_kw(peek(), {"NOT"}):
                pos += 1
                return not not_expr()
            return primary()

        def and_expr() -> bool:
            nonlocal pos
            result = not_expr()
            while is_kw(peek(), {"AND"}):
                pos += 1
                rhs = not_expr()
                result = result and rhs
            return result

        def or_expr() -> bool:
            nonlocal pos
            result = and_expr()
            while is_kw(peek(), {"OR"}):
                pos += 1
                rhs = and_expr()
                result = result or rhs
            return result

        return or_expr()

    # -- commands -------------------------------------------------------------------------------

    def abspath(self, path: str, base: str) -> str:
        return os.path.normpath(path if os.path.isabs(path) else os.path.join(base, path))

    def resolve_target(self, name: str) -> str:
        return self.aliases.get(name, name)

    def command(self, cmd: Command, vars: dict[str, str]) -> None:
        name = cmd.name
        if name in self.functions:
            self.call(self.functions[name], cmd, vars)
            return
        refs: list[str] = []
        args = self.expand_args(cmd.args, vars, refs)
        src_dir = vars["CMAKE_CURRENT_SOURCE_DIR"]
        bin_dir = vars["CMAKE_CURRENT_BINARY_DIR"]
        handler = getattr(self, "cmd_" + name, None)
        if handler:
            handler(cmd, args, vars, src_dir, bin_dir, refs)
        elif name in BLOCK_COMMANDS:
            raise CMakeError(f"{cmd.path}:{cmd.line}: {name}() without its opening command")

    def call(self, fn: Function, cmd: Command, vars: dict[str, str]) -> None:
        args = self.expand_args(cmd.args, vars)
        scope = vars if fn.is_macro else dict(vars)
        scope["ARGC"] = str(len(args))
        scope["ARGV"] = ";".join(args)
        scope["ARGN"] = ";".join(args[len(fn.params):])
        for k, a in enumerate(args):
            scope[f"ARGV{k}"] = a
        for p, a in zip(fn.params, args):
            scope[p] = a
        self.call_stack.append((fn, cmd))
        self._parents.append(vars)
        try:
            self.run(fn.body, scope)
        except Return:
            pass
        finally:
            self.call_stack.pop()
            self._parents.pop()
            if not fn.is_macro:
                self.glob_vars.pop(id(scope), None)

    def _globs_of(self, refs: list[str], vars) -> list[tuple[str, bool]]:
        known = self.glob_vars.get(id(vars), {})
        return [origin for ref in refs for origin in known.get(ref, [])]

    def cmd_set(self, cmd, args, vars, src_dir, bin_dir, refs):
        if not args:
            return
        var, values = args[0], args[1:]
        target = vars
        if values and values[-1] == "PARENT_SCOPE":
            values = values[:-1]
            target = self._parents[-1] if self._parents else vars
        if "CACHE" in values:
            values = values[:values.index("CACHE")]
            if var in vars:  # a cache entry does not replace a value already set (-D)
                return
        if values:
            target[var] = ";".join(values)
        else:
            target.pop(var, None)
        globs = self._globs_of(refs, vars)
        if globs:
            self.glob_vars.setdefault(id(target), {})[var] = globs
        else:
            self.glob_vars.get(id(target), {}).pop(var, None)

    def cmd_unset(self, cmd, args, vars, *_):
        if args:
            vars.pop(args[0], None)

    def cmd_option(self, cmd, args, vars, *_):
        # Every option on: the check covers every optional target. -D overrides.
        if args and args[0] not in vars:
            vars[args[0]] = "ON"

    def cmd_include(self, cmd, args, vars, *_):
        if args and args[0] == "CTest" and "BUILD_TESTING" not in vars:
            vars["BUILD_TESTING"] = "ON"

    def cmd_project(self, cmd, args, vars, *_):
        if args:
            vars["PROJECT_NAME"] = args[0]
            vars["PROJECT_SOURCE_DIR"] = vars["CMAKE_CURRENT_SOURCE_DIR"]
            vars[f"{args[0]}_SOURCE_DIR"] = vars["CMAKE_CURRENT_SOURCE_DIR"]
            if "VERSION" in args:
                version = args[args.index("VERSION") + 1]
                vars["PROJECT_VERSION"] = version

    def cmd_list(self, cmd, args, vars, src_dir, bin_dir, refs):
        if len(args) < 2:
            return
        op, var, rest = args[0].upper(), args[1], args[2:]
        items = split_list(vars.get(var, ""))
        if op == "APPEND":
            items += rest
            globs = self._globs_of(refs, vars)
            if globs:
                self.glob_vars.setdefault(id(vars), {}).setdefault(var, []).extend(globs)
        elif op == "PREPEND":
            items = rest + items
        elif op == "REMOVE_ITEM":
            items = [x for x in items if x not in rest]
        elif op == "REMOVE_DUPLICATES":
            items = list(dict.fromkeys(items))
        elif op == "SORT":
            items = sorted(items)
        elif op == "FILTER" and len(rest) >= 3:
            keep = rest[0] == "INCLUDE"
            items = [x for x in items if bool(re.search(rest[2], x)) == keep]
        else:
            return
        vars[var] = ";".join(items)

    def cmd_cmake_parse_arguments(self, cmd, args, vars, *_):
        if args and args[0] == "PARSE_ARGV":
            start, prefix, options, singles, multis = args[1:6]
            argn = [vars.get(f"ARGV{k}", "") for k in range(int(start), int(vars.get("ARGC", "0")))]
        elif len(args) >= 4:
            prefix, options, singles, multis = args[:4]
            argn = args[4:]
        else:
            return
        options, singles, multis = split_list(options), split_list(singles), split_list(multis)
        values: dict[str, list[str]] = {}
        current = None
        unparsed = []
        for a in argn:
            if a in options:
                values[a] = ["TRUE"]
                current = None
            elif a in singles or a in multis:
                values[a] = []
                current = a
            elif current is not None:
                values[current].append(a)
                if current in singles:
                    current = None
            else:
                unparsed.append(a)
        for o in options:
            vars[f"{prefix}_{o}"] = "TRUE" if o in values else "FALSE"
        for k in singles + multis:
            if values.get(k):
                vars[f"{prefix}_{k}"] = ";".join(values[k])
            else:
                vars.pop(f"{prefix}_{k}", None)
        if unparsed:
            vars[f"{prefix}_UNPARSED_ARGUMENTS"] = ";".join(unparsed)

    def _glob(self, patterns: list[str], recursive: bool, base: str, relative: str | None):
        files, origins = [], []
        for pattern in patterns:
            pattern = self.abspath(pattern, base)
            head, tail = os.path.split(pattern)
            while any(ch in head for ch in "*?["):
                head, part = os.path.split(head)
                tail = os.path.join(part, tail)
            origins.append((head, recursive))
            if not os.path.isdir(head):
                continue
            if recursive:
                for dirpath, dirnames, filenames in os.walk(head):
                    dirnames[:] = sorted(d for d in dirnames if not skip_dir(os.path.join(dirpath, d)))
                    for f in sorted(filenames):
                        full = os.path.join(dirpath, f)
                        # GLOB_RECURSE: the pattern's file part matches the file name anywhere below.
                        if fnmatch.fnmatchcase(full, pattern) or fnmatch.fnmatchcase(f, os.path.basename(pattern)):
                            files.append(full)
            else:
                for f in sorted(os.listdir(head)):
                    full = os.path.join(head, f)
                    if os.path.isfile(full) and fnmatch.fnmatchcase(full, pattern):
                        files.append(full)
        if relative:
            files = [os.path.relpath(f, relative) for f in files]
        return files, origins

    def cmd_file(self, cmd, args, vars, src_dir, bin_dir, refs):
        if not args:
            return
        op = args[0].upper()
        if op in ("GLOB", "GLOB_RECURSE") and len(args) >= 2:
            var, rest = args[1], args[2:]
            relative = None
            patterns = []
            k = 0
            while k < len(rest):
                word = rest[k]
                if word == "RELATIVE":
                    relative = rest[k + 1]
                    k += 2
                    continue
                if word == "LIST_DIRECTORIES":
                    k += 2
                    continue
                if word not in ("CONFIGURE_DEPENDS", "FOLLOW_SYMLINKS"):
                    patterns.append(word)
                k += 1
            files, origins = self._glob(patterns, op == "GLOB_RECURSE", src_dir, relative)
            vars[var] = ";".join(files)
            self.glob_vars.setdefault(id(vars), {})[var] = origins
        elif op in ("GENERATE", "CONFIGURE") and "OUTPUT" in args:
            out = args[args.index("OUTPUT") + 1]
            self.generated.add(self.abspath(out, bin_dir))
        elif op in ("WRITE", "APPEND", "TOUCH") and len(args) >= 2:
            self.generated.add(self.abspath(args[1], bin_dir))
        elif op in ("COPY_FILE",) and len(args) >= 3:
            self.generated.add(self.abspath(args[2], bin_dir))

    def cmd_configure_file(self, cmd, args, vars, src_dir, bin_dir, refs):
        if len(args) >= 2:
            out = self.abspath(args[1], bin_dir)
            if os.path.isdir(out) or args[1].endswith("/"):
                out = os.path.join(out, os.path.basename(args[0]))
            self.generated.add(out)

    def cmd_add_custom_command(self, cmd, args, vars, src_dir, bin_dir, refs):
        if args and args[0] == "OUTPUT":
            for a in args[1:]:
                if a.isupper() and a in ("COMMAND", "DEPENDS", "MAIN_DEPENDENCY", "WORKING_DIRECTORY",
                                         "COMMENT", "BYPRODUCTS", "VERBATIM", "IMPLICIT_DEPENDS",
                                         "DEPFILE", "JOB_POOL", "USES_TERMINAL", "APPEND"):
                    break
                self.generated.add(self.abspath(a, bin_dir))

    def cmd_add_subdirectory(self, cmd, args, vars, src_dir, bin_dir, refs):
        if not args:
            return
        sub_src = self.abspath(args[0], src_dir)
        sub_bin = self.abspath(args[1], bin_dir) if len(args) > 1 and args[1] != "EXCLUDE_FROM_ALL" \
            else self.abspath(args[0], bin_dir)
        listfile = os.path.join(sub_src, "CMakeLists.txt")
        if not os.path.isfile(listfile):
            raise CMakeError(f"{cmd.path}:{cmd.line}: add_subdirectory: no {listfile}")
        scope = dict(vars)
        scope["CMAKE_CURRENT_SOURCE_DIR"] = sub_src
        scope["CMAKE_CURRENT_BINARY_DIR"] = sub_bin
        scope["CMAKE_CURRENT_LIST_DIR"] = sub_src
        self._parents.append(vars)
        try:
            self.run_file(listfile, scope)
        finally:
            self._parents.pop()

    def _new_target(self, cmd, name, kind, src_dir, vars) -> Target:
        t = Target(name, kind, cmd.path, cmd.line, src_dir)
        if self.call_stack:
            fn, call = self.call_stack[0]
            t.via_function = fn.name
            t.path, t.line = call.path, call.line
            t.via_function_depends = any(a.kind == "unquoted" and a.text == "DEPENDS" for a in call.args)
        self.targets[name] = t
        return t

    def _add_sources(self, t: Target, items: list[str], src_dir: str, refs: list[str], vars) -> None:
        globs = [(head, recursive) for head, recursive in self._globs_of(refs, vars)
                 if head == self.root or head.startswith(self.root + os.sep)]
        for head, recursive in globs:
            t.owned_dirs[head] = t.owned_dirs.get(head, False) or recursive
        for item in items:
            if item.startswith("$<"):
                continue
            path = self.abspath(item, src_dir)
            t.sources.add(path)
            if path.startswith(self.root + os.sep) and not any(
                    recursive and path.startswith(head + os.sep) for head, recursive in globs):
                t.owned_dirs.setdefault(os.path.dirname(path), False)

    def cmd_add_library(self, cmd, args, vars, src_dir, bin_dir, refs):
        if not args:
            return
        name, rest = args[0], args[1:]
        if rest[:1] == ["ALIAS"]:
            self.aliases[name] = rest[1]
            return
        kind = "UNKNOWN"
        while rest and rest[0] in ("STATIC", "SHARED", "MODULE", "OBJECT", "INTERFACE", "UNKNOWN",
                                   "IMPORTED", "GLOBAL", "EXCLUDE_FROM_ALL"):
            if rest[0] == "IMPORTED":
                kind = "IMPORTED"
            elif rest[0] not in ("GLOBAL", "EXCLUDE_FROM_ALL") and kind != "IMPORTED":
                kind = rest[0]
            rest = rest[1:]
        t = self._new_target(cmd, name, kind, src_dir, vars)
        if kind != "IMPORTED":
            self._add_sources(t, rest, src_dir, refs, vars)

    def cmd_add_executable(self, cmd, args, vars, src_dir, bin_dir, refs):
        if not args:
            return
        name, rest = args[0], args[1:]
        if rest[:1] == ["ALIAS"]:
            self.aliases[name] = rest[1]
            return
        kind = "EXECUTABLE"
        while rest and rest[0] in ("WIN32", "MACOSX_BUNDLE", "EXCLUDE_FROM_ALL", "IMPORTED", "GLOBAL"):
            if rest[0] == "IMPORTED":
                kind = "IMPORTED"
            rest = rest[1:]
        t = self._new_target(cmd, name, kind, src_dir, vars)
        if kind != "IMPORTED":
            self._add_sources(t, rest, src_dir, refs, vars)

    def _scoped(self, args: list[str], default: str) -> list[tuple[str, str]]:
        scope, out = default, []
        for a in args:
            if a in ("PUBLIC", "PRIVATE", "INTERFACE"):
                scope = a
            elif a in ("LINK_PUBLIC", "LINK_PRIVATE", "LINK_INTERFACE_LIBRARIES"):
                scope = {"LINK_PUBLIC": "PUBLIC", "LINK_PRIVATE": "PRIVATE"}.get(a, "INTERFACE")
            elif a in ("SYSTEM", "BEFORE", "AFTER", "debug", "optimized", "general"):
                continue
            else:
                out.append((scope, a))
        return out

    def _target(self, name: str) -> Target | None:
        return self.targets.get(self.resolve_target(name))

    def cmd_target_link_libraries(self, cmd, args, vars, *_):
        t = self._target(args[0]) if args else None
        if t is None:
            return
        # The plain signature (no keyword) is transitive, like PUBLIC.
        for scope, item in self._scoped(args[1:], "PUBLIC"):
            for name in unwrap_genex(item):
                t.links.append((scope, name))

    def cmd_target_sources(self, cmd, args, vars, src_dir, bin_dir, refs):
        t = self._target(args[0]) if args else None
        if t is None:
            return
        # target_sources(t SCOPE files... [FILE_SET name [TYPE type] [BASE_DIRS dirs...] FILES files...])
        files, skip = [], None
        for scope, item in self._scoped(args[1:], "PRIVATE"):
            if item in ("FILE_SET", "TYPE", "BASE_DIRS"):
                skip = item
            elif item == "FILES":
                skip = None
            elif skip in ("FILE_SET", "TYPE"):
                skip = None  # their one value
            elif skip != "BASE_DIRS":
                files.append(item)
        for item in files:
            if item.startswith("$<"):
                continue
            path = self.abspath(item, src_dir)
            t.sources.add(path)

    def cmd_target_include_directories(self, cmd, args, vars, src_dir, *_):
        t = self._target(args[0]) if args else None
        if t is None:
            return
        for scope, item in self._scoped(args[1:], "PRIVATE"):
            for d in unwrap_genex(item):
                t.include_dirs.append((scope, self.abspath(d, src_dir)))

    def cmd_add_dependencies(self, cmd, args, vars, *_):
        t = self._target(args[0]) if args else None
        if t is not None:
            t.build_deps.extend(self.resolve_target(a) for a in args[1:])


BLOCK_COMMANDS = {"elseif", "else", "endif", "endforeach", "endwhile", "endfunction", "endmacro"}


def unwrap_genex(item: str) -> list[str]:
    """The targets or paths an item names: $<BUILD_INTERFACE:x>, $<TARGET_OBJECTS:x> and
    $<LINK_ONLY:x> name x; other generator expressions name nothing we can check."""
    m = re.fullmatch(r"\$<(BUILD_INTERFACE|TARGET_OBJECTS|LINK_ONLY|COMPILE_ONLY):(.*)>", item)
    if m:
        return unwrap_genex(m.group(2))
    if item.startswith("$<") or "$<" in item:
        return []
    return [item]


# ----------------------------------------------------------------------------------------------
# The model: who owns what, who links what.


class Model:
    def __init__(self, interp: Interpreter):
        self.root = interp.root
        self.generated = interp.generated
        self.aliases = interp.aliases
        self.targets = {n: t for n, t in interp.targets.items() if t.kind != "IMPORTED"}
        self.listfiles = interp.listfiles
        # Links between project targets only (imported and system libraries are not checked).
        self.links: dict[str, list[tuple[str, str]]] = {
            n: [(s, interp.resolve_target(d)) for s, d in t.links if interp.resolve_target(d) in self.targets]
            for n, t in self.targets.items()}
        self._closure: dict[str, set[str]] = {}

    def closure(self, name: str) -> set[str]:
        """The targets whose headers `name` may include: itself, its direct links, and what those
        link PUBLIC or INTERFACE, transitively."""
        if name in self._closure:
            return self._closure[name]
        result = {name}
        stack = [d for _, d in self.links.get(name, [])]
        while stack:
            d = stack.pop()
            if d in result:
                continue
            result.add(d)
            stack.extend(e for scope, e in self.links.get(d, []) if scope in ("PUBLIC", "INTERFACE"))
        self._closure[name] = result
        return result

    def depends_path(self, start: str, goal: str) -> list[tuple[str, str, str]] | None:
        """A chain of dependencies (link or add_dependencies) from start to goal, as
        (from, kind, to) steps, or None."""
        prev: dict[str, tuple[str, str]] = {}
        stack, seen = [start], {start}
        while stack:
            node = stack.pop()
            if node == goal:
                path = []
                while node != start:
                    p, kind = prev[node]
                    path.append((p, kind, node))
                    node = p
                return list(reversed(path))
            t = self.targets.get(node)
            edges = [(d, "links") for _, d in self.links.get(node, [])]
            if t:
                edges += [(d, "add_dependencies") for d in t.build_deps if d in self.targets]
            for d, kind in edges:
                if d not in seen:
                    seen.add(d)
                    prev[d] = (node, kind)
                    stack.append(d)
        return None

    def owners_of_dir(self, d: str) -> set[str]:
        owners = set()
        for name, t in self.targets.items():
            for owned, recursive in t.owned_dirs.items():
                if d == owned or (recursive and d.startswith(owned + os.sep)):
                    owners.add(name)
        return owners

    def owners_of_file(self, path: str) -> set[str]:
        return self.owners_of_dir(os.path.dirname(path)) | self.compiled_by(path)

    def compiled_by(self, path: str) -> set[str]:
        return {name for name, t in self.targets.items() if path in t.sources}

    def files_to_scan(self) -> dict[str, set[str]]:
        """Every C++ file of the targets' folders -> the targets whose include rules apply to it:
        the targets compiling it, or for a file no target compiles (a header), its folder's owners."""
        files: dict[str, set[str]] = {}
        for name, t in self.targets.items():
            for src in t.sources:
                if os.path.splitext(src)[1] in CXX_EXTENSIONS and os.path.isfile(src):
                    files.setdefault(src, set()).add(name)
        for name, t in self.targets.items():
            for d, recursive in t.owned_dirs.items():
                for path in walk_cxx(d, recursive):
                    if path in files and self.compiled_by(path):
                        continue
                    files.setdefault(path, set()).add(name)
        return files

    def include_dir_providers(self, d: str) -> set[str]:
        """Targets whose dependents get include directory d (PUBLIC or INTERFACE)."""
        return {n for n, t in self.targets.items() if any(s != "PRIVATE" and x == d for s, x in t.include_dirs)}

    def has_include_dir(self, name: str, d: str) -> bool:
        t = self.targets[name]
        if any(x == d for _, x in t.include_dirs):
            return True
        return any(other in self.include_dir_providers(d) for other in self.closure(name) - {name})


def skip_dir(path: str) -> bool:
    """Hidden folders and build trees (a CMakeCache.txt) are not globbed or scanned."""
    base = os.path.basename(path)
    return base.startswith(".") or os.path.exists(os.path.join(path, "CMakeCache.txt"))


def walk_cxx(d: str, recursive: bool):
    if not os.path.isdir(d):
        return
    if recursive:
        for dirpath, dirnames, filenames in os.walk(d):
            dirnames[:] = sorted(x for x in dirnames if not skip_dir(os.path.join(dirpath, x)))
            for f in sorted(filenames):
                if os.path.splitext(f)[1] in CXX_EXTENSIONS:
                    yield os.path.join(dirpath, f)
    else:
        for f in sorted(os.listdir(d)):
            full = os.path.join(d, f)
            if os.path.isfile(full) and os.path.splitext(f)[1] in CXX_EXTENSIONS:
                yield full


# ----------------------------------------------------------------------------------------------
# Includes


_INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*(?:"([^"\n]+)"|<([^>\n]+)>)')


def strip_comments(text: str) -> str:
    """The text with comments, string and character literals blanked (newlines kept), so that an
    #include in a comment or a raw string is not taken for one."""
    out, i, n = [], 0, len(text)
    at_line_start = True  # only whitespace since the last newline: a # here is a directive
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            # A line comment continues over a backslash-newline.
            while j > 0 and j < n and text[j - 1] == "\\":
                k = text.find("\n", j + 1)
                j = n if k < 0 else k
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "#" and at_line_start:
            # A directive: keep it whole (its "..." or <...> is the point), up to the line's end.
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(text[i:j])
            i = j
            at_line_start = False
        elif (m := re.match(r'(?:u8|[uUL])?R"([^ ()\\\t\n]{0,16})\(', text[i:i + 40])) and \
                (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = ")" + m.group(1) + '"'
            j = text.find(close, i + m.end())
            j = n if j < 0 else j + len(close)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            at_line_start = False
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            at_line_start = False
        else:
            out.append(c)
            if c == "\n":
                at_line_start = True
            elif not c.isspace():
                at_line_start = False
            i += 1
    return "".join(out)


def includes_of(path: str) -> list[tuple[int, str, bool]]:
    """(line, included path, quoted) of every #include "..." and #include <...> of a file."""
    with open(path, encoding="utf-8", errors="replace") as f:
        text = strip_comments(f.read())
    result = []
    for number, line in enumerate(text.split("\n"), 1):
        m = _INCLUDE.match(line)
        if m:
            result.append((number, m.group(1) or m.group(2), m.group(1) is not None))
    return result


@dataclass
class Violation:
    path: str
    line: int
    message: str


def check(source_dir: str, defines: dict[str, str]) -> tuple[list[Violation], str]:
    root = os.path.abspath(source_dir)
    interp = Interpreter(root, defines)
    vars = {
        "CMAKE_SOURCE_DIR": root, "CMAKE_BINARY_DIR": BINARY_DIR,
        "CMAKE_CURRENT_SOURCE_DIR": root, "CMAKE_CURRENT_BINARY_DIR": BINARY_DIR,
        "CMAKE_CURRENT_LIST_DIR": root, "PROJECT_SOURCE_DIR": root, "PROJECT_BINARY_DIR": BINARY_DIR,
        "CMAKE_COMMAND": "cmake", "CMAKE_DL_LIBS": "dl", "UNIX": "1", "CMAKE_SYSTEM_NAME": "Linux",
    }
    vars.update(defines)
    interp.run_file(os.path.join(root, "CMakeLists.txt"), vars)
    model = Model(interp)

    def rel(path: str) -> str:
        if path.startswith(BINARY_DIR + os.sep):
            return "<build>/" + os.path.relpath(path, BINARY_DIR)
        return os.path.relpath(path, root)

    def listfile_of(t: Target) -> str:
        return rel(t.path)

    def remedy(includer: str, owner: str) -> str:
        """What to write in which CMakeLists.txt, or why it cannot be written (a cycle)."""
        cycle = model.depends_path(owner, includer)
        if cycle:
            chain = ", ".join(f"{a} links {b}" if k == "links" else f"{a} depends on {b} through {k}"
                              for a, k, b in cycle)
            return (f"linking it would make a cycle ({chain}): move the code or split the "
                    f"target instead")
        t = model.targets[includer]
        if t.via_function and t.via_function_depends:
            return f"add it to DEPENDS in {listfile_of(t)}"
        return f"add it to target_link_libraries({includer} ...) in {listfile_of(t)}"

    # Include directories where headers are looked up: those of the source tree (the root, as
    # the project writes includes) and those in the build tree (generated headers).
    include_dirs = []
    for t in model.targets.values():
        for _, d in t.include_dirs:
            if d not in include_dirs:
                include_dirs.append(d)
    source_include_dirs = [d for d in include_dirs if d == root or d.startswith(root + os.sep)] or [root]
    generated_include_dirs = [d for d in include_dirs if d.startswith(BINARY_DIR + os.sep) or d == BINARY_DIR]

    violations: list[Violation] = []
    files = model.files_to_scan()
    checked = 0
    for path in sorted(files):
        includers = sorted(files[path])
        for line, inc, quoted in includes_of(path):
            spelled = f'"{inc}"' if quoted else f"<{inc}>"
            resolved = None
            if quoted:
                candidate = os.path.normpath(os.path.join(os.path.dirname(path), inc))
                if os.path.isfile(candidate):
                    resolved = candidate
            for d in source_include_dirs:
                # <name> without a folder is the standard library's (<memory>), never the root's.
                if resolved is None and (quoted or "/" in inc):
                    candidate = os.path.normpath(os.path.join(d, inc))
                    if os.path.isfile(candidate):
                        resolved = candidate
            generated_in = None
            if resolved is None:
                for d in generated_include_dirs:
                    if os.path.normpath(os.path.join(d, inc)) in model.generated:
                        generated_in = d
                        break
            if resolved is None and generated_in is None:
                # Not a file of the repository: a library's header, unless it names a folder of
                # the repository (a header that does not exist (yet): its folder decides).
                first = inc.split("/")[0]
                if "/" in inc and any(os.path.isdir(os.path.join(d, first)) for d in source_include_dirs):
                    resolved = os.path.normpath(os.path.join(source_include_dirs[0], inc))
                else:
                    continue
            checked += 1
            if generated_in is not None:
                providers = model.include_dir_providers(generated_in)
                for includer in includers:
                    if model.has_include_dir(includer, generated_in):
                        continue
                    owner = ", ".join(sorted(providers)) or "none"
                    fix = remedy(includer, sorted(providers)[0]) if providers else \
                        "no target puts its directory on the include path"
                    violations.append(Violation(rel(path), line,
                        f"includes {spelled} (generated into {rel(generated_in)}, target {owner}) "
                        f"but {includer} does not link it; {fix}"))
                continue
            folder = os.path.dirname(resolved)
            owners = model.owners_of_file(resolved)
            for includer in includers:
                if includer in owners or model.closure(includer) & owners:
                    continue
                if not owners:
                    violations.append(Violation(rel(path), line,
                        f"includes {spelled} but no target owns {rel(folder)}/ (so {includer} cannot "
                        f"link it); give the folder a target in CMakeLists.txt (candela_folder, or an "
                        f"INTERFACE library when it has only headers)"))
                    continue
                owner = sorted(owners)[0] if len(owners) == 1 else " or ".join(sorted(owners))
                violations.append(Violation(rel(path), line,
                    f"includes {spelled} (target {owner}) but {includer} does not link it; "
                    f"{remedy(includer, sorted(owners)[0])}"))
    summary = (f"check-include-deps: {len(files)} files and {checked} includes of the project's headers "
               f"checked against the {len(model.targets)} targets of "
               f"{', '.join(rel(p) for p in model.listfiles)}: every include is linked")
    return violations, summary


# ----------------------------------------------------------------------------------------------
# Self-test: a small project in a temporary directory, checked clean and then with violations.


def self_test() -> int:
    import tempfile
    import unittest

    def write(root, rel_path, text):
        path = os.path.join(root, rel_path)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)

    project = r'''
cmake_minimum_required(VERSION 3.18)
project(Demo VERSION 1.2.3 LANGUAGES CXX)
configure_file(base/version.h.in ${CMAKE_BINARY_DIR}/generated/demo/version.h)
function(demo_folder name)
  cmake_parse_arguments(ARG "" "" "FOLDERS;DEPENDS" ${ARGN})
  set(globs)
  foreach(folder ${ARG_FOLDERS})
    list(APPEND globs ${folder}/*.cpp)
  endforeach()
  file(GLOB sources CONFIGURE_DEPENDS ${globs})
  add_library(${name} OBJECT ${sources})
  target_link_libraries(${name} PUBLIC ${ARG_DEPENDS})
endfunction()
file(GLOB BASE_SOURCES CONFIGURE_DEPENDS base/*.cpp)
add_library(demo_base OBJECT ${BASE_SOURCES})
target_include_directories(demo_base PUBLIC ${CMAKE_SOURCE_DIR} ${CMAKE_BINARY_DIR}/generated)
demo_folder(demo_low FOLDERS low DEPENDS demo_base)
demo_folder(demo_mid FOLDERS mid mid/sub DEPENDS demo_base)  # [[ a comment ]]
demo_folder(demo_top FOLDERS top DEPENDS demo_mid)
#[[ demo_folder(demo_commented FOLDERS low) ]]
add_library(demo_headers INTERFACE)
target_sources(demo_headers INTERFACE hdr/only.h)
add_library(demo_module MODULE plug/plug.cpp)
add_dependencies(demo_base demo_module)
option(DEMO_APPS "apps" OFF)
if(DEMO_APPS AND NOT "${CMAKE_BINARY_DIR}" STREQUAL "")
  add_subdirectory(app)
endif()
'''
    files = {
        "CMakeLists.txt": project,
        "base/version.h.in": "#define V \"@PROJECT_VERSION@\"\n",
        "base/base.h": "#pragma once\n",
        "base/base.cpp": '#include "base/base.h"\n#include <demo/version.h>\n#include <vector>\n',
        "low/low.h": '#pragma once\n#include "base/base.h"\n',
        "low/low.cpp": '#include "low/low.h"\n',
        "mid/mid.cpp": '#include "mid/sub/sub.h"\n#include "base/base.h"\n',
        "mid/sub/sub.h": '#pragma once\n',
        "mid/sub/sub.cpp": '#include "sub.h"\n',
        "top/top.cpp": ('#include "mid/sub/sub.h"\n#include "base/base.h"\n'
                        '// #include "low/low.h" in a comment\n'
                        'const char* s = R"(\n#include "low/low.h"\n)";\n'
                        '/*\n#include "low/low.h"\n*/\n'),
        "hdr/only.h": "#pragma once\n",
        "plug/plug.cpp": "#include <vector>\n",
        "app/CMakeLists.txt": ("file(GLOB_RECURSE APP_SOURCES CONFIGURE_DEPENDS *.cpp)\n"
                               "add_executable(demo_app ${APP_SOURCES})\n"
                               "add_library(demo_all INTERFACE)\n"
                               "foreach(lib demo_base demo_low demo_top)\n"
                               "  target_link_libraries(demo_all INTERFACE ${lib} $<TARGET_OBJECTS:${lib}>)\n"
                               "endforeach()\n"
                               "target_link_libraries(demo_app PRIVATE demo_all)\n"),
        "app/main.cpp": '#include "low/low.h"\n#include "mid/sub/sub.h"\n#include "app/inner/x.h"\n',
        "app/inner/x.h": "#pragma once\n",
    }

    class Tests(unittest.TestCase):
        def setUp(self):
            self.dir = tempfile.TemporaryDirectory()
            self.root = self.dir.name
            for k, v in files.items():
                write(self.root, k, v)

        def tearDown(self):
            self.dir.cleanup()

        def run_check(self):
            return check(self.root, {})

        def assert_one_violation(self, *fragments):
            """The demo tree has exactly one violation, whose message says each fragment."""
            violations = self.run_check()[0]
            self.assertEqual(len(violations), 1)
            for fragment in fragments:
                self.assertIn(fragment, violations[0].message)

        def test_parser(self):
            commands = parse_cmake('a(x "y ${z}" [=[w]=] (p q)) # c\nB(\n  "m\nn"\n)\n', "t")
            self.assertEqual([c.name for c in commands], ["a", "b"])
            self.assertEqual([x.text for x in commands[0].args], ["x", "y ${z}", "w", "(", "p", "q", ")"])
            self.assertEqual(commands[1].line, 2)
            self.assertEqual(commands[1].args[0].text, "m\nn")

        def test_graph(self):
            interp = Interpreter(self.root, {})
            interp.run_file(os.path.join(self.root, "CMakeLists.txt"),
                            {"CMAKE_SOURCE_DIR": self.root, "CMAKE_BINARY_DIR": BINARY_DIR,
                             "CMAKE_CURRENT_SOURCE_DIR": self.root, "CMAKE_CURRENT_BINARY_DIR": BINARY_DIR})
            model = Model(interp)
            self.assertEqual(model.closure("demo_top"), {"demo_top", "demo_mid", "demo_base"})
            self.assertEqual(model.closure("demo_app"), {"demo_app", "demo_all", "demo_base", "demo_low",
                                                         "demo_top", "demo_mid"})
            self.assertEqual(model.owners_of_dir(os.path.join(self.root, "mid", "sub")), {"demo_mid"})
            self.assertEqual(model.owners_of_dir(os.path.join(self.root, "app", "inner")), {"demo_app"})
            self.assertEqual(model.owners_of_file(os.path.join(self.root, "hdr", "only.h")), {"demo_headers"})
            self.assertIn(os.path.join(BINARY_DIR, "generated", "demo", "version.h"), model.generated)
            self.assertTrue(model.targets["demo_low"].via_function_depends)

        def test_clean(self):
            violations, summary = self.run_check()
            self.assertEqual(violations, [], "\n".join(v.message for v in violations))
            self.assertIn("includes", summary)

        def test_missing_dependency(self):
            write(self.root, "low/low2.cpp", '#include "base/base.h"\n\n#include "mid/sub/sub.h"\n')
            violations, _ = self.run_check()
            self.assertEqual([(v.path, v.line, v.message) for v in violations], [(
                os.path.join("low", "low2.cpp"), 3,
                'includes "mid/sub/sub.h" (target demo_mid) but demo_low does not link it; '
                "add it to DEPENDS in CMakeLists.txt")])

        def test_private_link_does_not_propagate(self):
            text = files["CMakeLists.txt"].replace("demo_folder(demo_top FOLDERS top DEPENDS demo_mid)",
                                                   "demo_folder(demo_top FOLDERS top)\n"
                                                   "target_link_libraries(demo_top PRIVATE demo_mid)")
            text = text.replace("add_subdirectory(app)", "")
            write(self.root, "CMakeLists.txt", text)
            self.assertEqual(self.run_check()[0], [])
            write(self.root, "low/low.cpp", '#include "top/top.h"\n')
            write(self.root, "top/top.h", '#pragma once\n')
            text = text.replace("DEPENDS demo_base)\ndemo_folder(demo_mid", "DEPENDS demo_base demo_top)\ndemo_folder(demo_mid")
            write(self.root, "CMakeLists.txt", text)
            write(self.root, "low/low.cpp", '#include "top/top.h"\n#include "mid/sub/sub.h"\n')
            self.assert_one_violation('"mid/sub/sub.h" (target demo_mid) but demo_low does not link it')

        def test_unowned_folder(self):
            write(self.root, "loose/loose.h", "#pragma once\n")
            write(self.root, "mid/mid.cpp", '#include "loose/loose.h"\n')
            self.assert_one_violation("no target owns loose/")

        def test_header_only_target(self):
            write(self.root, "mid/mid.cpp", '#include "hdr/only.h"\n')
            self.assert_one_violation("(target demo_headers) but demo_mid does not link it")

        def test_generated_header(self):
            write(self.root, "plug/plug.cpp", "#include <demo/version.h>\n")
            self.assert_one_violation("generated into <build>/generated")

        def test_cycle(self):
            write(self.root, "plug/plug.cpp", '#include "base/base.h"\n')
            self.assert_one_violation("demo_module does not link it", "cycle (demo_base depends on demo_module through add_dependencies)")

        def test_header_checked_for_its_folder(self):
            write(self.root, "low/low.h", '#pragma once\n#include "top/top.h"\n')
            write(self.root, "top/top.h", '#pragma once\n')
            violations = self.run_check()[0]
            self.assertEqual([(v.path, v.line) for v in violations], [(os.path.join("low", "low.h"), 2)])

    suite = unittest.defaultTestLoader.loadTestsFromTestCase(Tests)
    result = unittest.TextTestRunner(verbosity=2).run(suite)
    return 0 if result.wasSuccessful() else 1


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--source-dir", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."),
                        help="the repository (default: the parent of scripts/)")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="VAR=VALUE",
                        help="a CMake variable's value (default: every option() ON, BUILD_TESTING ON)")
    parser.add_argument("--self-test", action="store_true", help="run the script's own tests")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    defines = dict(d.split("=", 1) if "=" in d else (d, "ON") for d in args.defines)
    try:
        violations, summary = check(args.source_dir, defines)
    except (CMakeError, OSError) as e:
        print(f"check-include-deps: {e}", file=sys.stderr)
        return 2
    for v in violations:
        print(f"{v.path}:{v.line}: {v.message}")
    if violations:
        print(f"check-include-deps: {len(violations)} include(s) cross to a target that is not linked",
              file=sys.stderr)
        return 1
    print(summary)
    return 0


if __name__ == "__main__":
    sys.exit(main())
