//! The project's own architecture test: it reads the sources under `src/` and the ```` ```layers ```` block
//! of ARCHITECTURE.md, and fails when files import each other around a circle, when a file uses a module or
//! an external crate its layer may not use, or when a file or a function outgrows its limit.
//!
//! # How the code is read (std only, no parser crate)
//! - A small tokenizer drops comments (kept aside for the `long:` reasons), string, char and number
//!   literals, so `// use crate::shell` or `"crate::shell"` import nothing.
//! - Each file is split into module scopes (the file, and each inline `mod name { ... }` in it) with the
//!   names each scope defines (`struct`, `enum`, `fn`, `const`, ...), its child modules (`mod x;` or
//!   `mod x { }`; a declaration is not an import) and its `use` declarations, flattened (groups, nested groups,
//!   `self`, `as`, globs; `pub`, `pub(crate)` or private). Paths written in code (`crate::render::Instance`,
//!   `super::cpu::use_avx2()`, `rayon::join`) are collected too, attributes included (`bytemuck::Pod` in a
//!   derive).
//! - Crates: `src/lib.rs` and every file under `src/` outside `src/main.rs` and `src/bin/` is the library,
//!   which the binaries call by its name from Cargo.toml (`scanline_racer::`); `src/main.rs` is a binary of
//!   one file; `src/bin/NAME/` (root `main.rs`) and `src/bin/NAME.rs` are binaries whose `crate::` is their
//!   own folder.
//! - A path is resolved segment by segment as the compiler does: `crate`, `self`, `super`, child modules (the
//!   file `a.rs` or `a/mod.rs`, or an inline `mod a { }`, which belongs to the file holding it), and the
//!   names a module imports, re-exported or not (`pub use sub::Thing`, `pub use sub::{A, B}`,
//!   `pub use sub::*`), followed recursively to the file that defines the name: `use super::DrawList`, where
//!   `render/mod.rs` has `pub use options::DrawList`, is an arrow to `render/options.rs`, not to
//!   `render/mod.rs`. The target is the file defining the item (an enum's variant or an associated item
//!   counts as its type's), or the file of the last module reached. A last name the reader cannot find in
//!   its module (an item a macro makes) counts as that module's file; a path into our own crates that cannot
//!   be followed before its last name fails the layer test, since the reader has missed something. A first
//!   segment that is a dependency in Cargo.toml (or `std`, `core`, `alloc`) names that external crate.
//! - Test code: an item under `#[cfg(test)]` (a `mod tests { }`, a `use`, a function) and a whole file
//!   declared `#[cfg(test)] mod x;` import "test-only". Test-only arrows are kept apart: the circle check
//!   ignores them (a test module reaching back into its parent is no circle in the shipped code), the layer
//!   rules hold them like any other code.
//!
//! # The checks
//! 1. No circle: the arrows between files (self-arrows ignored, test-only arrows ignored) have no cycle.
//!    Each cycle is printed as `src/a.rs -> src/b.rs -> src/a.rs` with the names that tie each arrow.
//! 2. Layers, from the ```` ```layers ```` block of ARCHITECTURE.md: one rule a line,
//!    `MODULE: internal modules it may use | external crates it may name`, `#` starting a comment. MODULE is
//!    a path under `src/` without `.rs`/`mod.rs` (`render`, `render/core`, `bin/assetgen`). A file belongs
//!    to the rule with the longest MODULE that is its path or a folder above it (`src/render/geometry/clip.rs`
//!    to `render/geometry` if that rule exists, else to `render`); `src/lib.rs` and `src/main.rs` are the
//!    root, which may use everything unless a `(root)` rule is written. An arrow from a file of module X to a
//!    file of module Y is allowed when Y is X, when Y is inside X (a parent may use its children, whose own
//!    rules are checked for their files), or when Y is, or is inside, a module listed for X. Nothing else:
//!    a child may not use its parent unless the parent is listed (records flow down). Every external crate
//!    a file names must be listed for its module (`std`, `core` and `alloc` always may be). Every file must
//!    belong to a rule; every listed module must have a rule; every listed crate must be a dependency in
//!    Cargo.toml; every rule must hold at least one file.
//! 3. Size: no file under `src/` over 500 lines (tests included); no function over 80 lines (from the `fn`
//!    line to its closing brace) unless a comment containing `long:` and the reason sits directly above it
//!    (above its doc comment and attributes, or among them).
//!
//! Each check is a function from the sources (held in memory) to a list of problems; the tests at the end
//! run them on the real tree and on small made-up trees that must fail.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fs;
use std::path::Path;

/// Longest file under `src/`, in lines.
const MAX_FILE_LINES: usize = 500;
/// Longest function without a written `long:` reason, in lines.
const MAX_FN_LINES: usize = 80;
/// External crates every module may name.
const ALWAYS_ALLOWED_CRATES: [&str; 3] = ["std", "core", "alloc"];
/// The module name of the crate roots `src/lib.rs` and `src/main.rs`.
const ROOT: &str = "(root)";

// ---------------------------------------------------------------------------------------------------------
// The sources
// ---------------------------------------------------------------------------------------------------------

/// Everything the checks read, in memory: the real repository, or a made-up one in the self-tests.
struct Tree {
    /// Rust files under `src/`, by path relative to `src/` (`render/mod.rs`), with their text.
    files: BTreeMap<String, String>,
    /// The text of ARCHITECTURE.md.
    architecture: String,
    /// The text of Cargo.toml.
    manifest: String,
}

impl Tree {
    /// Reads `src/**/*.rs`, ARCHITECTURE.md and Cargo.toml under `root`.
    fn load(root: &Path) -> Tree {
        let mut files = BTreeMap::new();
        collect_rust_files(&root.join("src"), "", &mut files);
        Tree { files, architecture: read(&root.join("ARCHITECTURE.md")), manifest: read(&root.join("Cargo.toml")) }
    }

    /// The repository this test belongs to.
    fn real() -> Tree {
        Tree::load(Path::new(env!("CARGO_MANIFEST_DIR")))
    }
}

/// The text of `path`; a file that cannot be read fails the test with its name.
fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// Adds every `.rs` file under `dir` to `out`, keyed by its path below `src/` (`prefix` is `dir`'s).
fn collect_rust_files(dir: &Path, prefix: &str, out: &mut BTreeMap<String, String>) {
    let entries = fs::read_dir(dir).unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()));
    for entry in entries {
        let path = entry.unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display())).path();
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        if path.is_dir() {
            collect_rust_files(&path, &format!("{prefix}{name}/"), out);
        } else if name.ends_with(".rs") {
            out.insert(format!("{prefix}{name}"), read(&path));
        }
    }
}

// ---------------------------------------------------------------------------------------------------------
// Tokenizer
// ---------------------------------------------------------------------------------------------------------

/// A token of Rust source; literals and lifetimes keep no text, since no check looks into them.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Tok {
    /// An identifier or keyword (`r#type` is `type`).
    Ident(String),
    /// `::`.
    PathSep,
    /// Any other punctuation character, one at a time.
    Punct(char),
    /// A string, char or number literal.
    Literal,
    /// A lifetime or loop label.
    Lifetime,
}

/// A token and the line it starts on (1-based).
#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    line: usize,
}

/// A comment (line, block or doc) and the line it starts on.
#[derive(Clone, Debug)]
struct Comment {
    line: usize,
    text: String,
}

/// Splits Rust source into tokens and comments.
struct Lexer {
    chars: Vec<char>,
    pos: usize,
    line: usize,
    tokens: Vec<Token>,
    comments: Vec<Comment>,
}

/// Whether `c` may start an identifier.
fn is_ident_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

/// Whether `c` may continue an identifier.
fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

impl Lexer {
    /// Tokens and comments of `src`.
    fn lex(src: &str) -> (Vec<Token>, Vec<Comment>) {
        let mut lexer =
            Lexer { chars: src.chars().collect(), pos: 0, line: 1, tokens: Vec::new(), comments: Vec::new() };
        lexer.run();
        (lexer.tokens, lexer.comments)
    }

    /// The character `k` places ahead (`'\0'` past the end).
    fn peek(&self, k: usize) -> char {
        self.chars.get(self.pos + k).copied().unwrap_or('\0')
    }

    /// Consumes one character, counting lines.
    fn bump(&mut self) -> char {
        let c = self.peek(0);
        if c == '\n' {
            self.line += 1;
        }
        self.pos += 1;
        c
    }

    /// Emits a token.
    fn push(&mut self, tok: Tok, line: usize) {
        self.tokens.push(Token { tok, line });
    }

    /// Whether the whole source is read.
    fn at_end(&self) -> bool {
        self.pos >= self.chars.len()
    }

    /// Reads the whole source.
    fn run(&mut self) {
        while !self.at_end() {
            let (c, line) = (self.peek(0), self.line);
            if c.is_whitespace() {
                self.bump();
            } else if c == '/' && self.peek(1) == '/' {
                let start = self.pos;
                while !self.at_end() && self.peek(0) != '\n' {
                    self.bump();
                }
                self.comments.push(Comment { line, text: self.chars[start..self.pos].iter().collect() });
            } else if c == '/' && self.peek(1) == '*' {
                self.block_comment(line);
            } else if c == '"' {
                self.bump();
                self.string_body();
                self.push(Tok::Literal, line);
            } else if c == '\'' {
                self.quote(line);
            } else if let Some((prefix, hashes)) = self.raw_string_start() {
                self.raw_string(prefix, hashes);
                self.push(Tok::Literal, line);
            } else if (c == 'b' || c == 'c') && self.peek(1) == '"' {
                self.bump();
                self.bump();
                self.string_body();
                self.push(Tok::Literal, line);
            } else if c == 'b' && self.peek(1) == '\'' {
                self.bump();
                self.quote(line);
            } else if c == 'r' && self.peek(1) == '#' && is_ident_start(self.peek(2)) {
                self.pos += 2;
                self.ident(line);
            } else if is_ident_start(c) {
                self.ident(line);
            } else if c.is_ascii_digit() {
                self.number(line);
            } else if c == ':' && self.peek(1) == ':' {
                self.pos += 2;
                self.push(Tok::PathSep, line);
            } else {
                self.bump();
                self.push(Tok::Punct(c), line);
            }
        }
    }

    /// A `/* */` comment, nested ones included.
    fn block_comment(&mut self, line: usize) {
        let start = self.pos;
        let mut depth = 0usize;
        while !self.at_end() {
            if self.peek(0) == '/' && self.peek(1) == '*' {
                depth += 1;
                self.pos += 2;
            } else if self.peek(0) == '*' && self.peek(1) == '/' {
                depth -= 1;
                self.pos += 2;
                if depth == 0 {
                    break;
                }
            } else {
                self.bump();
            }
        }
        self.comments.push(Comment { line, text: self.chars[start..self.pos].iter().collect() });
    }

    /// The rest of a quoted string after its opening `"`, escapes included.
    fn string_body(&mut self) {
        while !self.at_end() {
            match self.bump() {
                '\\' => {
                    self.bump();
                }
                '"' => return,
                _ => {}
            }
        }
    }

    /// `r"`, `r#"`, `br##"`, `cr"`...: the prefix length and the number of `#`.
    fn raw_string_start(&self) -> Option<(usize, usize)> {
        let prefix = match (self.peek(0), self.peek(1)) {
            ('r', _) => 1,
            ('b' | 'c', 'r') => 2,
            _ => return None,
        };
        let hashes = (0..).take_while(|&k| self.peek(prefix + k) == '#').count();
        (self.peek(prefix + hashes) == '"').then_some((prefix, hashes))
    }

    /// A raw string: its prefix, `#`s and quote, then up to a quote followed by as many `#`s.
    fn raw_string(&mut self, prefix: usize, hashes: usize) {
        self.pos += prefix + hashes + 1;
        while !self.at_end() {
            if self.bump() == '"' && (0..hashes).all(|k| self.peek(k) == '#') {
                self.pos += hashes;
                return;
            }
        }
    }

    /// At a `'`: a char literal (`'a'`, `'\n'`, `'\u{1F600}'`) or a lifetime / label (`'a`, `'outer`).
    fn quote(&mut self, line: usize) {
        if self.peek(1) == '\\' {
            self.pos += 2;
            self.bump();
            while !self.at_end() && self.bump() != '\'' {}
            self.push(Tok::Literal, line);
        } else if self.peek(2) == '\'' {
            self.bump();
            self.bump();
            self.bump();
            self.push(Tok::Literal, line);
        } else {
            self.bump();
            while is_ident_char(self.peek(0)) {
                self.bump();
            }
            self.push(Tok::Lifetime, line);
        }
    }

    /// An identifier or keyword.
    fn ident(&mut self, line: usize) {
        let start = self.pos;
        while is_ident_char(self.peek(0)) {
            self.bump();
        }
        let word = self.chars[start..self.pos].iter().collect();
        self.push(Tok::Ident(word), line);
    }

    /// A number; a `.` belongs to it when a digit follows (`1.5`, not `0..n`).
    fn number(&mut self, line: usize) {
        while is_ident_char(self.peek(0)) || (self.peek(0) == '.' && self.peek(1).is_ascii_digit()) {
            self.bump();
        }
        self.push(Tok::Literal, line);
    }
}

/// For every bracket token, the index of its partner (`(` with `)`, `[` with `]`, `{` with `}`, both ways).
fn bracket_pairs(tokens: &[Token]) -> Vec<Option<usize>> {
    let mut pairs = vec![None; tokens.len()];
    let mut open = Vec::new();
    for (i, t) in tokens.iter().enumerate() {
        match t.tok {
            Tok::Punct('(' | '[' | '{') => open.push(i),
            Tok::Punct(')' | ']' | '}') => {
                if let Some(o) = open.pop() {
                    pairs[o] = Some(i);
                    pairs[i] = Some(o);
                }
            }
            _ => {}
        }
    }
    pairs
}

// ---------------------------------------------------------------------------------------------------------
// One file: scopes, imports, paths, functions
// ---------------------------------------------------------------------------------------------------------

/// One flattened `use`: `use a::{b::C, d as e, f::*}` gives `a::b::C` bound as `C`, `a::d` as `e`, and
/// the glob `a::f::*`.
#[derive(Clone, Debug)]
struct UseItem {
    /// The path as written (`["super", "span", "Row"]`); a leading `::` is kept as a `"::"` segment.
    path: Vec<String>,
    /// The name it binds (`"*"` for a glob).
    name: String,
    glob: bool,
    line: usize,
    /// Under `#[cfg(test)]`.
    test: bool,
}

/// A path written in code or in an attribute, with at least one `::` (`crate::render::Instance`).
#[derive(Clone, Debug)]
struct PathRef {
    path: Vec<String>,
    line: usize,
    test: bool,
}

/// A module scope: the file itself, or an inline `mod name { ... }` in it.
#[derive(Clone, Debug, Default)]
struct Scope {
    /// The inline modules leading to it inside the file (empty for the file itself).
    inline: Vec<String>,
    /// Items it defines: `struct`, `enum`, `union`, `trait`, `type`, `fn`, `const`, `static`, `macro_rules!`.
    defined: BTreeSet<String>,
    /// Child modules it declares (`mod x;` and `mod x { }`).
    children: BTreeSet<String>,
    /// Child modules declared under `#[cfg(test)]`.
    test_children: BTreeSet<String>,
    uses: Vec<UseItem>,
    paths: Vec<PathRef>,
}

/// A function with a body.
#[derive(Clone, Debug)]
struct FnInfo {
    name: String,
    /// The line of `fn`.
    line: usize,
    /// From the `fn` line to the line of its closing brace, both included.
    lines: usize,
    /// A comment containing `long:` sits directly above it.
    has_long_reason: bool,
}

/// What the checks need of one source file.
#[derive(Clone, Debug)]
struct SourceFile {
    lines: usize,
    /// The file's own scope first, then its inline modules.
    scopes: Vec<Scope>,
    fns: Vec<FnInfo>,
}

/// Item keywords whose next identifier is a name the module defines.
const ITEM_KEYWORDS: [&str; 8] = ["struct", "enum", "union", "trait", "type", "fn", "const", "static"];
/// Words that may stand between an item's attributes and its `fn`.
const FN_QUALIFIERS: [&str; 7] = ["pub", "crate", "const", "async", "unsafe", "extern", "default"];

/// Reads one file.
fn parse_file(text: &str) -> SourceFile {
    let (tokens, comments) = Lexer::lex(text);
    let pairs = bracket_pairs(&tokens);
    let test = test_mask(&tokens, &pairs);
    let mut parser = FileParser { tokens: &tokens, test: &test, scopes: vec![Scope::default()] };
    parser.run();
    let fns = functions(&tokens, &pairs, &comments);
    SourceFile { lines: text.lines().count(), scopes: parser.scopes, fns }
}

/// The identifier at `i`, if that token is one.
fn ident_at(tokens: &[Token], i: usize) -> Option<&str> {
    match tokens.get(i).map(|t| &t.tok) {
        Some(Tok::Ident(w)) => Some(w),
        _ => None,
    }
}

/// Whether the token at `i` is `tok`.
fn is_at(tokens: &[Token], i: usize, tok: &Tok) -> bool {
    tokens.get(i).is_some_and(|t| &t.tok == tok)
}

/// Marks the tokens of every item under `#[cfg(test)]` (or `#[cfg(all(test, ...))]`): the attribute, any
/// further attributes, and the item up to its `;` or its closing brace.
fn test_mask(tokens: &[Token], pairs: &[Option<usize>]) -> Vec<bool> {
    let mut mask = vec![false; tokens.len()];
    for i in 0..tokens.len() {
        let is_cfg_test = is_at(tokens, i, &Tok::Punct('#'))
            && is_at(tokens, i + 1, &Tok::Punct('['))
            && ident_at(tokens, i + 2) == Some("cfg")
            && is_at(tokens, i + 3, &Tok::Punct('('))
            && ((ident_at(tokens, i + 4) == Some("test") && is_at(tokens, i + 5, &Tok::Punct(')')))
                || (ident_at(tokens, i + 4) == Some("all")
                    && is_at(tokens, i + 5, &Tok::Punct('('))
                    && ident_at(tokens, i + 6) == Some("test")));
        if !is_cfg_test {
            continue;
        }
        let Some(attr_end) = pairs[i + 1] else { continue };
        let end = item_end(tokens, pairs, attr_end + 1);
        for m in &mut mask[i..=end] {
            *m = true;
        }
    }
    mask
}

/// The last token of the item starting at `start` (after an attribute): its `;`, or the closing brace of
/// its first top-level `{ }`.
fn item_end(tokens: &[Token], pairs: &[Option<usize>], start: usize) -> usize {
    let last = tokens.len().saturating_sub(1);
    let mut j = start;
    while let Some(t) = tokens.get(j) {
        match t.tok {
            Tok::Punct('{') => return pairs[j].unwrap_or(last),
            Tok::Punct('(' | '[') => j = pairs[j].map_or(last, |c| c + 1),
            Tok::Punct(';') => return j,
            _ => j += 1,
        }
    }
    last
}

/// Walks a file's tokens once, filling its scopes.
struct FileParser<'a> {
    tokens: &'a [Token],
    test: &'a [bool],
    scopes: Vec<Scope>,
}

impl FileParser<'_> {
    /// One pass: brace depth tells item level (a module's body) from code inside functions and impls.
    fn run(&mut self) {
        let t = self.tokens;
        // Open scopes: (index in `scopes`, brace depth of its body).
        let mut open: Vec<(usize, usize)> = vec![(0, 0)];
        let mut depth = 0usize;
        let mut i = 0;
        while i < t.len() {
            let (scope, body_depth) = open.last().copied().unwrap_or((0, 0));
            let at_item_level = depth == body_depth;
            let after_path_sep = i > 0 && t[i - 1].tok == Tok::PathSep;
            match &t[i].tok {
                Tok::Punct('{') => depth += 1,
                Tok::Punct('}') => {
                    depth = depth.saturating_sub(1);
                    if open.len() > 1 && depth < body_depth {
                        open.pop();
                    }
                }
                Tok::Ident(w) if w == "use" && !after_path_sep => {
                    i = self.use_declaration(scope, i);
                    continue;
                }
                Tok::Ident(w) if w == "mod" => {
                    if let Some(name) = ident_at(t, i + 1) {
                        let name = name.to_string();
                        self.scopes[scope].children.insert(name.clone());
                        if self.test[i] {
                            self.scopes[scope].test_children.insert(name.clone());
                        }
                        if is_at(t, i + 2, &Tok::Punct('{')) {
                            let mut inline = self.scopes[scope].inline.clone();
                            inline.push(name);
                            self.scopes.push(Scope { inline, ..Scope::default() });
                            depth += 1;
                            open.push((self.scopes.len() - 1, depth));
                            i += 3;
                            continue;
                        }
                    }
                }
                Tok::Ident(w) if at_item_level && w == "macro_rules" => {
                    if let Some(name) = ident_at(t, i + 2) {
                        self.scopes[scope].defined.insert(name.to_string());
                    }
                }
                Tok::Ident(w) if at_item_level && ITEM_KEYWORDS.contains(&w.as_str()) => {
                    let skip_mut = usize::from(ident_at(t, i + 1) == Some("mut"));
                    if let Some(name) = ident_at(t, i + 1 + skip_mut)
                        && !matches!(name, "fn" | "unsafe" | "async" | "extern")
                    {
                        self.scopes[scope].defined.insert(name.to_string());
                    }
                }
                _ => {}
            }
            if !after_path_sep && ident_at(t, i).is_some_and(|w| w != "Self") {
                self.inline_path(scope, i);
            }
            i += 1;
        }
    }

    /// Records the `use` declaration whose `use` is at `i`; returns the index after its `;`.
    fn use_declaration(&mut self, scope: usize, i: usize) -> usize {
        let mut leaves = Vec::new();
        let mut next = parse_use_tree(self.tokens, i + 1, &[], &mut leaves);
        while next < self.tokens.len() && !is_at(self.tokens, next, &Tok::Punct(';')) {
            next += 1;
        }
        let (line, test) = (self.tokens[i].line, self.test[i]);
        for (mut path, alias, glob) in leaves {
            if path.last().is_some_and(|s| s == "self") {
                path.pop();
            }
            let name = match (glob, alias) {
                (true, _) => "*".to_string(),
                (false, Some(alias)) => alias,
                (false, None) => path.last().cloned().unwrap_or_default(),
            };
            self.scopes[scope].uses.push(UseItem { path, name, glob, line, test });
        }
        next + 1
    }

    /// Records the path starting at `i` if it has a `::` (`a::b`, `crate::x::y()`).
    fn inline_path(&mut self, scope: usize, i: usize) {
        let t = self.tokens;
        let mut path = Vec::new();
        if i > 0 && t[i - 1].tok == Tok::PathSep && (i < 2 || ident_at(t, i - 2).is_none()) {
            path.push("::".to_string());
        }
        let mut j = i;
        while let Some(seg) = ident_at(t, j) {
            path.push(seg.to_string());
            if !is_at(t, j + 1, &Tok::PathSep) {
                break;
            }
            j += 2;
        }
        if path.len() >= 2 {
            self.scopes[scope].paths.push(PathRef { path, line: t[i].line, test: self.test[i] });
        }
    }
}

/// One leaf of a use tree: the full path, the `as` name, whether it is a glob.
type UseLeaf = (Vec<String>, Option<String>, bool);

/// Parses the use tree at `i` below `prefix` into `out`; returns the index after it.
fn parse_use_tree(tokens: &[Token], mut i: usize, prefix: &[String], out: &mut Vec<UseLeaf>) -> usize {
    let mut path = prefix.to_vec();
    if is_at(tokens, i, &Tok::PathSep) {
        if path.is_empty() {
            path.push("::".to_string());
        }
        i += 1;
    }
    loop {
        match tokens.get(i).map(|t| &t.tok) {
            Some(Tok::Punct('*')) => {
                out.push((path, None, true));
                return i + 1;
            }
            Some(Tok::Punct('{')) => {
                i += 1;
                while tokens.get(i).is_some_and(|t| t.tok != Tok::Punct('}')) {
                    let next = parse_use_tree(tokens, i, &path, out);
                    i = if is_at(tokens, next, &Tok::Punct(',')) { next + 1 } else { next.max(i + 1) };
                }
                return i + 1;
            }
            Some(Tok::Ident(seg)) => {
                path.push(seg.clone());
                i += 1;
                if is_at(tokens, i, &Tok::PathSep) {
                    i += 1;
                    continue;
                }
                let alias = (ident_at(tokens, i) == Some("as")).then(|| ident_at(tokens, i + 1).map(str::to_string));
                if alias.is_some() {
                    i += 2;
                }
                out.push((path, alias.flatten(), false));
                return i;
            }
            _ => return i,
        }
    }
}

/// Every function with a body: where it starts, how long it is, and whether a `long:` reason sits above it
/// (a comment between the previous code token and the `fn`: above or among its doc comment and attributes).
fn functions(tokens: &[Token], pairs: &[Option<usize>], comments: &[Comment]) -> Vec<FnInfo> {
    let mut fns = Vec::new();
    for i in 0..tokens.len() {
        let (Some("fn"), Some(name)) = (ident_at(tokens, i), ident_at(tokens, i + 1)) else { continue };
        let mut j = i + 2;
        let body = loop {
            match tokens.get(j).map(|t| &t.tok) {
                Some(Tok::Punct('{')) => break Some(j),
                Some(Tok::Punct(';')) | None => break None,
                Some(Tok::Punct('(' | '[')) => j = pairs[j].map_or(tokens.len(), |c| c + 1),
                _ => j += 1,
            }
        };
        let Some(close) = body.and_then(|b| pairs[b]) else { continue };
        let start = item_start(tokens, pairs, i);
        let above = if start == 0 { 0 } else { tokens[start - 1].line };
        let fn_line = tokens[i].line;
        let has_long_reason = comments.iter().any(|c| c.line > above && c.line < fn_line && c.text.contains("long:"));
        fns.push(FnInfo {
            name: name.to_string(),
            line: fn_line,
            lines: tokens[close].line - fn_line + 1,
            has_long_reason,
        });
    }
    fns
}

/// The first token of the item whose `fn` is at `i`: back over `pub(crate)`, `const`, `unsafe`,
/// `extern "C"`, ... and over `#[...]` attributes.
fn item_start(tokens: &[Token], pairs: &[Option<usize>], i: usize) -> usize {
    let mut k = i;
    while k > 0 {
        match &tokens[k - 1].tok {
            Tok::Ident(w) if FN_QUALIFIERS.contains(&w.as_str()) => k -= 1,
            Tok::Literal => k -= 1,
            Tok::Punct(')') => match pairs[k - 1] {
                Some(o) if o > 0 && ident_at(tokens, o - 1) == Some("pub") => k = o - 1,
                _ => break,
            },
            Tok::Punct(']') => match pairs[k - 1] {
                Some(o) if o > 0 && is_at(tokens, o - 1, &Tok::Punct('#')) => k = o - 1,
                _ => break,
            },
            _ => break,
        }
    }
    k
}

// ---------------------------------------------------------------------------------------------------------
// Crates and the resolver
// ---------------------------------------------------------------------------------------------------------

/// A module: the crate it is in (`"lib"`, `"main.rs"`, `"bin/assetgen/"`) and its path in that crate.
type ModKey = (String, Vec<String>);

/// The crate and module path of a file, from where it lies under `src/`.
fn module_key(rel: &str) -> ModKey {
    let (krate, inner) = if rel == "main.rs" {
        ("main.rs".to_string(), "main.rs")
    } else if let Some(bin) = rel.strip_prefix("bin/") {
        match bin.split_once('/') {
            Some((name, inner)) => (format!("bin/{name}/"), inner),
            None => (rel.to_string(), "main.rs"),
        }
    } else {
        ("lib".to_string(), rel)
    };
    let stem = inner.strip_suffix(".rs").unwrap_or(inner);
    let stem = stem.strip_suffix("/mod").unwrap_or(stem);
    let path = if stem == "main" || stem == "lib" || stem == "mod" {
        Vec::new()
    } else {
        stem.split('/').map(str::to_string).collect()
    };
    (krate, path)
}

/// What a path names.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Resolved {
    /// A module (a file or an inline module).
    Module(ModKey),
    /// An item defined in this file (index into [`Resolver::rels`]).
    Item(usize),
    /// An external crate.
    External(String),
    /// Nothing the reader knows (a local type parameter, `Vec::new`, a std prelude type).
    Unknown,
}

/// Resolves paths across all files.
struct Resolver {
    /// File paths below `src/`, in the order of `files`.
    rels: Vec<String>,
    files: Vec<SourceFile>,
    /// Every scope by module: (file index, scope index in the file).
    scopes: HashMap<ModKey, (usize, usize)>,
    /// Names of external crates (dependencies, `std`, `core`, `alloc`).
    externals: BTreeSet<String>,
    /// The library's crate name, as the binaries write it.
    lib_name: String,
}

/// How deep re-exports and globs are followed before giving up (a guard against import loops).
const MAX_RESOLVE_DEPTH: usize = 12;

/// The parent module (the root stays the root).
fn parent(key: &ModKey) -> ModKey {
    let mut path = key.1.clone();
    path.pop();
    (key.0.clone(), path)
}

impl Resolver {
    /// Reads every file of `tree` and indexes its scopes by module.
    fn new(tree: &Tree) -> Resolver {
        let manifest = Manifest::parse(&tree.manifest);
        let rels: Vec<String> = tree.files.keys().cloned().collect();
        let files: Vec<SourceFile> = tree.files.values().map(|text| parse_file(text)).collect();
        let mut scopes = HashMap::new();
        for (f, (rel, file)) in rels.iter().zip(&files).enumerate() {
            let (krate, path) = module_key(rel);
            for (s, scope) in file.scopes.iter().enumerate() {
                let mut full = path.clone();
                full.extend(scope.inline.iter().cloned());
                scopes.insert((krate.clone(), full), (f, s));
            }
        }
        let mut externals = manifest.dependencies;
        externals.extend(ALWAYS_ALLOWED_CRATES.iter().map(|c| c.to_string()));
        Resolver { rels, files, scopes, externals, lib_name: manifest.lib_name }
    }

    /// The file and scope of a module.
    fn scope(&self, key: &ModKey) -> Option<(usize, &Scope)> {
        self.scopes.get(key).map(|&(f, s)| (f, &self.files[f].scopes[s]))
    }

    /// What `path`, written in module `from`, names.
    fn resolve(&self, from: &ModKey, path: &[String], depth: usize) -> Resolved {
        let Some((first, rest)) = path.split_first() else { return Resolved::Unknown };
        if depth > MAX_RESOLVE_DEPTH {
            return Resolved::Unknown;
        }
        let mut here = match first.as_str() {
            "crate" => (from.0.clone(), Vec::new()),
            "self" => from.clone(),
            "super" => parent(from),
            "::" => return rest.first().map_or(Resolved::Unknown, |c| Resolved::External(c.clone())),
            name if name == self.lib_name && from.0 != "lib" => ("lib".to_string(), Vec::new()),
            name => match self.lookup(from, name, depth) {
                Resolved::Module(key) => key,
                Resolved::Unknown if self.externals.contains(name) => return Resolved::External(name.to_string()),
                other => return other,
            },
        };
        for (k, seg) in rest.iter().enumerate() {
            match seg.as_str() {
                "self" => continue,
                "super" => here = parent(&here),
                name => match self.lookup(&here, name, depth) {
                    Resolved::Module(key) => here = key,
                    // The last name, not found: an item a macro makes; taken to live in the module's file.
                    Resolved::Unknown if k + 1 == rest.len() => {
                        return self.scope(&here).map_or(Resolved::Unknown, |(f, _)| Resolved::Item(f));
                    }
                    other => return other,
                },
            }
        }
        if self.scopes.contains_key(&here) { Resolved::Module(here) } else { Resolved::Unknown }
    }

    /// What `name` means inside module `key`: a child module, an item it defines, or what it imports under
    /// that name (followed to where it is defined), directly or through a glob.
    fn lookup(&self, key: &ModKey, name: &str, depth: usize) -> Resolved {
        let Some((file, scope)) = self.scope(key) else { return Resolved::Unknown };
        if scope.children.contains(name) {
            let mut child = key.clone();
            child.1.push(name.to_string());
            return if self.scopes.contains_key(&child) { Resolved::Module(child) } else { Resolved::Item(file) };
        }
        if scope.defined.contains(name) {
            return Resolved::Item(file);
        }
        for u in scope.uses.iter().filter(|u| !u.glob && u.name == name) {
            match self.resolve(key, &u.path, depth + 1) {
                Resolved::Unknown => {}
                found => return found,
            }
        }
        for u in scope.uses.iter().filter(|u| u.glob) {
            if let Resolved::Module(glob) = self.resolve(key, &u.path, depth + 1)
                && &glob != key
            {
                match self.lookup(&glob, name, depth + 1) {
                    Resolved::Unknown => {}
                    found => return found,
                }
            }
        }
        Resolved::Unknown
    }

    /// The file a resolved path lands in, if it is one of ours.
    fn file_of(&self, resolved: &Resolved) -> Option<usize> {
        match resolved {
            Resolved::Module(key) => self.scopes.get(key).map(|&(f, _)| f),
            Resolved::Item(f) => Some(*f),
            _ => None,
        }
    }

    /// The segment of `path` that names the item it lands on: `Controls` for `crate::game::Controls::default`
    /// (the last segment when the path names a module).
    fn tie_name(&self, from: &ModKey, path: &[String]) -> String {
        if path.is_empty() {
            return String::new();
        }
        let item_end = (1..=path.len()).find(|&k| !matches!(self.resolve(from, &path[..k], 0), Resolved::Module(_)));
        path[item_end.unwrap_or(path.len()).max(1) - 1].clone()
    }

    /// Whether file `f` is compiled for tests only (declared `#[cfg(test)] mod x;` by its parent).
    fn is_test_file(&self, f: usize) -> bool {
        let key = module_key(&self.rels[f]);
        let Some(name) = key.1.last() else { return false };
        self.scope(&parent(&key)).is_some_and(|(_, scope)| scope.test_children.contains(name))
    }
}

/// What the checks need from Cargo.toml.
struct Manifest {
    /// The library's name (`[lib] name`, else the package's) with `-` as `_`: how the binaries name it.
    lib_name: String,
    /// Every dependency, dev- and build-dependency, with `-` as `_`.
    dependencies: BTreeSet<String>,
}

impl Manifest {
    /// Reads the `[package]` name and the keys of every dependency table (`[dependencies]`,
    /// `[dev-dependencies]`, `[target.'...'.dependencies]`, `[dependencies.name]`).
    fn parse(text: &str) -> Manifest {
        let mut lib_name = String::new();
        let mut dependencies = BTreeSet::new();
        let mut section = String::new();
        for line in text.lines().map(str::trim) {
            if let Some(header) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
                section = header.trim().to_string();
                if let Some((table, name)) = section.rsplit_once('.')
                    && table.ends_with("dependencies")
                {
                    dependencies.insert(name.replace('-', "_"));
                }
                continue;
            }
            let Some((key, value)) = line.split_once('=') else { continue };
            let key = key.trim();
            if ((section == "package" && lib_name.is_empty()) || section == "lib") && key == "name" {
                lib_name = value.trim().trim_matches('"').replace('-', "_");
            } else if section.ends_with("dependencies") && !key.starts_with('#') {
                dependencies.insert(key.replace('-', "_"));
            }
        }
        Manifest { lib_name, dependencies }
    }
}

// ---------------------------------------------------------------------------------------------------------
// The graph
// ---------------------------------------------------------------------------------------------------------

/// One place a file names another file (or an external crate).
#[derive(Clone, Debug)]
struct Ref {
    /// The path as written (`super::pipeline::DrawPolygon`).
    written: String,
    /// The name that ties the arrow: the segment naming the item (`DrawPolygon`, `Controls` in
    /// `Controls::default`).
    name: String,
    line: usize,
    test: bool,
}

/// The files under `src/` and who imports whom.
struct Graph {
    /// Paths below `src/`.
    rels: Vec<String>,
    /// Arrows between different files, with every place that makes them.
    edges: BTreeMap<(usize, usize), Vec<Ref>>,
    /// Per file, the external crates it names, with the places.
    externals: Vec<BTreeMap<String, Vec<Ref>>>,
    /// Paths into our own crates (`crate::`, `super::`, `self::`, the library's name) that reach no module:
    /// the reader has missed something, so the layer test fails on them.
    unresolved: Vec<String>,
}

impl Graph {
    /// Reads and resolves every file of `tree`.
    fn build(tree: &Tree) -> Graph {
        let resolver = Resolver::new(tree);
        let mut edges: BTreeMap<(usize, usize), Vec<Ref>> = BTreeMap::new();
        let mut externals = vec![BTreeMap::<String, Vec<Ref>>::new(); resolver.rels.len()];
        let mut unresolved = Vec::new();
        for (f, file) in resolver.files.iter().enumerate() {
            let test_file = resolver.is_test_file(f);
            let (krate, path) = module_key(&resolver.rels[f]);
            for scope in &file.scopes {
                let mut module = path.clone();
                module.extend(scope.inline.iter().cloned());
                let key = (krate.clone(), module);
                let uses = scope.uses.iter().map(|u| (&u.path, u.glob, u.line, u.test));
                let paths = scope.paths.iter().map(|p| (&p.path, false, p.line, p.test));
                for (segments, glob, line, test) in uses.chain(paths) {
                    let resolved = resolver.resolve(&key, segments, 0);
                    let name = if glob { "*".to_string() } else { resolver.tie_name(&key, segments) };
                    let written = segments.join("::") + if glob { "::*" } else { "" };
                    let reference = Ref { written, name, line, test: test || test_file };
                    let ours = ["crate", "super", "self", resolver.lib_name.as_str()];
                    if resolved == Resolved::Unknown && segments.first().is_some_and(|s| ours.contains(&s.as_str())) {
                        unresolved.push(format!(
                            "src/{}:{line}: `{}` reaches no module",
                            resolver.rels[f], reference.written
                        ));
                    } else if let Resolved::External(krate) = &resolved {
                        externals[f].entry(krate.clone()).or_default().push(reference);
                    } else if let Some(target) = resolver.file_of(&resolved)
                        && target != f
                    {
                        edges.entry((f, target)).or_default().push(reference);
                    }
                }
            }
        }
        Graph { rels: resolver.rels, edges, externals, unresolved }
    }

    /// `src/` and the file's path.
    fn show(&self, f: usize) -> String {
        format!("src/{}", self.rels[f])
    }
}

/// The distinct names of `refs` (non-test ones only when `shipped_only`), with the first line.
fn tie_names(refs: &[Ref], shipped_only: bool) -> String {
    let mut names: Vec<&str> = Vec::new();
    let mut line = usize::MAX;
    for r in refs.iter().filter(|r| !shipped_only || !r.test) {
        if !names.contains(&r.name.as_str()) {
            names.push(&r.name);
        }
        line = line.min(r.line);
    }
    format!("{} (line {line})", names.join(", "))
}

// ---------------------------------------------------------------------------------------------------------
// Check 1: no circle
// ---------------------------------------------------------------------------------------------------------

/// Printed cycles at most; the count of the rest is given.
const MAX_CYCLES_SHOWN: usize = 100;

/// Every elementary cycle of the shipped code's arrows, each with the names that tie its arrows.
fn cycle_problems(graph: &Graph) -> Vec<String> {
    let n = graph.rels.len();
    let mut next = vec![Vec::new(); n];
    for (&(a, b), refs) in &graph.edges {
        if refs.iter().any(|r| !r.test) {
            next[a].push(b);
        }
    }
    let mut cycles = Vec::new();
    let mut total = 0usize;
    for start in 0..n {
        // Cycles whose smallest file is `start`: depth-first through larger files only, so each is found once.
        let mut path = vec![start];
        let mut on_path = vec![false; n];
        on_path[start] = true;
        let mut stack = vec![0usize];
        while let Some(&top) = path.last() {
            let k = stack.last().copied().unwrap_or(0);
            if let Some(&to) = next[top].get(k) {
                if let Some(s) = stack.last_mut() {
                    *s += 1;
                }
                if to == start {
                    total += 1;
                    if cycles.len() < MAX_CYCLES_SHOWN {
                        cycles.push(describe_cycle(graph, &path));
                    }
                } else if to > start && !on_path[to] {
                    path.push(to);
                    on_path[to] = true;
                    stack.push(0);
                }
            } else {
                on_path[top] = false;
                path.pop();
                stack.pop();
            }
        }
    }
    if total > cycles.len() {
        cycles.push(format!("... and {} more cycles", total - cycles.len()));
    }
    cycles
}

/// `src/a.rs -> src/b.rs -> src/a.rs`, then each arrow with its names.
fn describe_cycle(graph: &Graph, path: &[usize]) -> String {
    let mut loop_files: Vec<usize> = path.to_vec();
    loop_files.push(path[0]);
    let mut text =
        format!("import circle: {}", loop_files.iter().map(|&f| graph.show(f)).collect::<Vec<_>>().join(" -> "));
    for pair in loop_files.windows(2) {
        let refs = graph.edges.get(&(pair[0], pair[1])).map_or(&[][..], Vec::as_slice);
        text += &format!("\n    {} -> {}: {}", graph.show(pair[0]), graph.show(pair[1]), tie_names(refs, true));
    }
    text
}

// ---------------------------------------------------------------------------------------------------------
// Check 2: layers
// ---------------------------------------------------------------------------------------------------------

/// One line of the ```` ```layers ```` block.
#[derive(Clone, Debug)]
struct Rule {
    module: String,
    internal: Vec<String>,
    external: Vec<String>,
    /// Its line in ARCHITECTURE.md.
    line: usize,
}

/// The rules of the ```` ```layers ```` block of ARCHITECTURE.md, or what is wrong with its format.
fn parse_layers(markdown: &str) -> Result<Vec<Rule>, Vec<String>> {
    let mut lines = markdown.lines().enumerate();
    if !lines.any(|(_, l)| l.trim() == "```layers") {
        return Err(vec!["ARCHITECTURE.md has no ```layers block".to_string()]);
    }
    let mut rules = Vec::new();
    let mut errors = Vec::new();
    for (index, raw) in lines {
        let line = index + 1;
        if raw.trim_start().starts_with("```") {
            return if errors.is_empty() { Ok(rules) } else { Err(errors) };
        }
        let text = raw.split('#').next().unwrap_or_default().trim();
        if text.is_empty() {
            continue;
        }
        let parsed = text.split_once(':').and_then(|(module, lists)| {
            let (internal, external) = lists.split_once('|')?;
            let module = module.trim();
            (!module.is_empty() && !module.contains(char::is_whitespace)).then(|| Rule {
                module: module.to_string(),
                internal: internal.split_whitespace().map(str::to_string).collect(),
                external: external.split_whitespace().map(str::to_string).collect(),
                line,
            })
        });
        match parsed {
            Some(rule) => rules.push(rule),
            None => errors
                .push(format!("ARCHITECTURE.md:{line}: `{text}` is not `MODULE: internal modules | external crates`")),
        }
    }
    errors.push("ARCHITECTURE.md: the ```layers block is not closed".to_string());
    Err(errors)
}

/// The file's path below `src/` as a module name: `render/mod.rs` is `render`, `render/clip.rs` is
/// `render/clip`.
fn module_name(rel: &str) -> &str {
    let stem = rel.strip_suffix(".rs").unwrap_or(rel);
    stem.strip_suffix("/mod").unwrap_or(stem)
}

/// The rule a file belongs to: [`ROOT`] for the crate roots, else the longest rule naming its module or a
/// folder above it.
fn rule_of(rel: &str, rules: &[Rule]) -> Option<String> {
    if rel == "lib.rs" || rel == "main.rs" {
        return Some(ROOT.to_string());
    }
    let name = module_name(rel);
    rules.iter().filter(|r| is_in(name, &r.module)).max_by_key(|r| r.module.len()).map(|r| r.module.clone())
}

/// Whether module `inner` is `outer` or inside it (`render/core` is inside `render`; `renderer` is not).
fn is_in(inner: &str, outer: &str) -> bool {
    inner == outer || inner.strip_prefix(outer).is_some_and(|rest| rest.starts_with('/'))
}

/// Everything that breaks the layer rules, or the block's own format and consistency.
fn layer_problems(tree: &Tree, graph: &Graph) -> Vec<String> {
    let rules = match parse_layers(&tree.architecture) {
        Ok(rules) => rules,
        Err(errors) => return errors,
    };
    let by_name: BTreeMap<&str, &Rule> = rules.iter().map(|r| (r.module.as_str(), r)).collect();
    let mut problems = block_problems(&rules, &Manifest::parse(&tree.manifest), graph);
    problems.extend(graph.unresolved.iter().cloned());
    let owners: Vec<Option<String>> = graph.rels.iter().map(|rel| rule_of(rel, &rules)).collect();
    for (f, owner) in owners.iter().enumerate() {
        if owner.is_none() {
            let top = module_name(&graph.rels[f]).split('/').next().unwrap_or_default();
            problems.push(format!(
                "{} belongs to no rule: add a line `{top}: ... | ...` to the ```layers block of ARCHITECTURE.md",
                graph.show(f)
            ));
        }
    }
    for (&(from, to), refs) in &graph.edges {
        let (Some(x), Some(y)) = (&owners[from], &owners[to]) else { continue };
        let rule = by_name.get(x.as_str());
        if rule.is_none() && x == ROOT {
            continue;
        }
        let listed = rule.map_or(&[][..], |r| r.internal.as_slice());
        if is_in(y, x) || listed.iter().any(|l| is_in(y, l)) {
            continue;
        }
        problems.push(format!(
            "{} (module `{x}`) uses {} (module `{y}`): {}\n    `{x}` may use only the modules inside it{} \
             (ARCHITECTURE.md:{}); a module does not get to use its parent or a sibling it does not list",
            graph.show(from),
            graph.show(to),
            show_refs(refs),
            if listed.is_empty() { String::new() } else { format!(" and [{}]", listed.join(" ")) },
            rule.map_or(0, |r| r.line)
        ));
    }
    for (f, crates) in graph.externals.iter().enumerate() {
        let Some(x) = &owners[f] else { continue };
        let rule = by_name.get(x.as_str());
        if rule.is_none() && x == ROOT {
            continue;
        }
        let listed = rule.map_or(&[][..], |r| r.external.as_slice());
        for (krate, refs) in crates {
            if ALWAYS_ALLOWED_CRATES.contains(&krate.as_str()) || listed.contains(krate) {
                continue;
            }
            problems.push(format!(
                "{} (module `{x}`) names the external crate `{krate}`: {}\n    `{x}` may name only [{}] \
                 and std, core, alloc (ARCHITECTURE.md:{})",
                graph.show(f),
                show_refs(refs),
                listed.join(" "),
                rule.map_or(0, |r| r.line)
            ));
        }
    }
    problems
}

/// Places shown per arrow or crate; the rest are counted.
const MAX_REFS_SHOWN: usize = 4;

/// The places of an arrow: `` `crate::shell::window` (line 3, test code) ``, ...
fn show_refs(refs: &[Ref]) -> String {
    let mut shown: Vec<String> = refs
        .iter()
        .take(MAX_REFS_SHOWN)
        .map(|r| format!("`{}` (line {}{})", r.written, r.line, if r.test { ", test code" } else { "" }))
        .collect();
    if refs.len() > MAX_REFS_SHOWN {
        shown.push(format!("and {} more", refs.len() - MAX_REFS_SHOWN));
    }
    shown.join(", ")
}

/// Mistakes in the block itself: a rule twice, a listed module without a rule, a crate that is no
/// dependency, a rule that no file belongs to.
fn block_problems(rules: &[Rule], manifest: &Manifest, graph: &Graph) -> Vec<String> {
    let mut problems = Vec::new();
    let names: BTreeSet<&str> = rules.iter().map(|r| r.module.as_str()).collect();
    let mut seen = BTreeSet::new();
    for rule in rules {
        let at = format!("ARCHITECTURE.md:{}: `{}`", rule.line, rule.module);
        if !seen.insert(rule.module.as_str()) {
            problems.push(format!("{at} has a second rule"));
        }
        for module in rule.internal.iter().filter(|m| !names.contains(m.as_str()) && m.as_str() != ROOT) {
            problems.push(format!("{at} lists `{module}`, which has no rule of its own"));
        }
        for krate in &rule.external {
            let known = ALWAYS_ALLOWED_CRATES.contains(&krate.as_str()) || manifest.dependencies.contains(krate);
            if !known {
                problems.push(format!("{at} lists `{krate}`, which is not a dependency in Cargo.toml"));
            }
        }
        let used = rule.module == ROOT
            || graph.rels.iter().any(|rel| rule_of(rel, rules).as_deref() == Some(rule.module.as_str()));
        if !used {
            problems.push(format!("{at}: no file under src/ belongs to this rule"));
        }
    }
    problems
}

// ---------------------------------------------------------------------------------------------------------
// Check 3: size
// ---------------------------------------------------------------------------------------------------------

/// Files over [`MAX_FILE_LINES`] and functions over [`MAX_FN_LINES`] without a `long:` reason.
fn size_problems(tree: &Tree) -> Vec<String> {
    let mut problems = Vec::new();
    for (rel, text) in &tree.files {
        let file = parse_file(text);
        if file.lines > MAX_FILE_LINES {
            problems.push(format!("src/{rel}: {} lines (at most {MAX_FILE_LINES})", file.lines));
        }
        for f in file.fns.iter().filter(|f| f.lines > MAX_FN_LINES && !f.has_long_reason) {
            problems.push(format!(
                "src/{rel}:{} fn {}: {} lines (at most {MAX_FN_LINES}, or a `// long: why` comment above it)",
                f.line, f.name, f.lines
            ));
        }
    }
    problems
}

/// Fails with every problem, one a paragraph, under `title`.
fn assert_none(title: &str, problems: &[String]) {
    assert!(problems.is_empty(), "{title} ({} problems):\n\n{}\n", problems.len(), problems.join("\n\n"));
}

// ---------------------------------------------------------------------------------------------------------
// The checks on the real tree
// ---------------------------------------------------------------------------------------------------------

#[test]
fn no_import_circle_between_files_under_src() {
    let graph = Graph::build(&Tree::real());
    assert!(!graph.edges.is_empty(), "the reader found no import at all under src/: the checker is broken");
    assert_none("files under src/ import each other around a circle", &cycle_problems(&graph));
}

#[test]
fn every_import_follows_the_layers_of_architecture_md() {
    let tree = Tree::real();
    let graph = Graph::build(&tree);
    assert!(!graph.edges.is_empty(), "the reader found no import at all under src/: the checker is broken");
    assert_none("imports that break the ```layers block of ARCHITECTURE.md", &layer_problems(&tree, &graph));
}

#[test]
fn no_file_over_500_lines_and_no_unexplained_fn_over_80() {
    assert_none("files or functions too long", &size_problems(&Tree::real()));
}

/// Not a check: prints every arrow between files and between modules of the ```layers block, to write or
/// review the block (`cargo test --test integration architecture::print_import_graph -- --ignored --nocapture`).
#[test]
#[ignore = "prints the import graph; run it by name with --ignored --nocapture"]
fn print_import_graph() {
    let tree = Tree::real();
    let graph = Graph::build(&tree);
    let rules = parse_layers(&tree.architecture).unwrap_or_default();
    let mut modules: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (&(a, b), refs) in &graph.edges {
        let test = if refs.iter().all(|r| r.test) { "  [test only]" } else { "" };
        println!("{} -> {}: {}{test}", graph.show(a), graph.show(b), tie_names(refs, false));
        let owner = |f: usize| rule_of(&graph.rels[f], &rules).unwrap_or_else(|| "?".to_string());
        modules.entry(owner(a)).or_default().insert(owner(b));
    }
    for (f, crates) in graph.externals.iter().enumerate() {
        let owner = rule_of(&graph.rels[f], &rules).unwrap_or_else(|| "?".to_string());
        let entry = modules.entry(owner).or_default();
        entry.extend(crates.keys().map(|c| format!("crate {c}")));
    }
    for (module, uses) in &modules {
        println!("{module}: {}", uses.iter().cloned().collect::<Vec<_>>().join(" "));
    }
}

// ---------------------------------------------------------------------------------------------------------
// The checker must be able to fail: made-up trees
// ---------------------------------------------------------------------------------------------------------

/// Made-up trees the checks must fail on (and pass on).
mod self_tests {
    use super::*;

    const MANIFEST: &str = "[package]\nname = \"toy-crate\"\n\n[dependencies]\nglam = \"0.34\"\n\
                            rayon = \"1\"\nwinit = \"0.30\"\n";

    /// A tree of `files` (path below `src/`, text) with this layers block.
    fn toy(files: &[(&str, &str)], layers: &str) -> Tree {
        Tree {
            files: files.iter().map(|(p, t)| (p.to_string(), t.to_string())).collect(),
            architecture: format!("# Architecture\n\nIntro.\n\n```layers\n{layers}\n```\n"),
            manifest: MANIFEST.to_string(),
        }
    }

    /// The arrows of `tree` as `a.rs -> b.rs` (paths below `src/`), test-only ones marked.
    fn arrows(tree: &Tree) -> Vec<String> {
        let graph = Graph::build(tree);
        graph
            .edges
            .iter()
            .map(|(&(a, b), refs)| {
                let test = if refs.iter().all(|r| r.test) { " (test)" } else { "" };
                format!("{} -> {}{test}", graph.rels[a], graph.rels[b])
            })
            .collect()
    }

    const ALL_MAY_USE_ALL: &str = "a: b | \nb: a |";

    #[test]
    fn a_circle_is_found_and_named_with_what_ties_it() {
        let tree = toy(
            &[
                ("lib.rs", "pub mod a;\npub mod b;\n"),
                ("a.rs", "use crate::b::Bee;\npub struct Ant;\n"),
                ("b.rs", "pub struct Bee;\nfn f() -> crate::a::Ant { crate::a::Ant }\n"),
            ],
            ALL_MAY_USE_ALL,
        );
        let cycles = cycle_problems(&Graph::build(&tree));
        assert_eq!(cycles.len(), 1, "{cycles:?}");
        assert!(cycles[0].contains("src/a.rs -> src/b.rs -> src/a.rs"), "{}", cycles[0]);
        assert!(cycles[0].contains("src/a.rs -> src/b.rs: Bee (line 1)"), "{}", cycles[0]);
        assert!(cycles[0].contains("src/b.rs -> src/a.rs: Ant (line 2)"), "{}", cycles[0]);
    }

    #[test]
    fn a_longer_circle_is_found_and_test_code_makes_none() {
        let tree = toy(
            &[
                ("lib.rs", "pub mod a;\npub mod b;\npub mod c;\n"),
                ("a.rs", "use super::b::B;\npub struct A;\n"),
                ("b.rs", "use super::c::C;\npub struct B;\n#[cfg(test)]\nmod tests {\n    use crate::a::A;\n}\n"),
                ("c.rs", "pub struct C;\nfn f() { let _ = super::a::A; }\n"),
            ],
            ALL_MAY_USE_ALL,
        );
        let cycles = cycle_problems(&Graph::build(&tree));
        assert_eq!(cycles.len(), 1, "{cycles:?}");
        assert!(cycles[0].contains("src/a.rs -> src/b.rs -> src/c.rs -> src/a.rs"), "{}", cycles[0]);
        assert!(arrows(&tree).contains(&"b.rs -> a.rs (test)".to_string()), "{:?}", arrows(&tree));

        let without_c = toy(
            &[
                ("lib.rs", "pub mod a;\npub mod b;\n"),
                ("a.rs", "use super::b::B;\npub struct A;\n"),
                ("b.rs", "pub struct B;\n#[cfg(test)]\nmod tests {\n    use crate::a::A;\n}\n"),
            ],
            ALL_MAY_USE_ALL,
        );
        assert!(cycle_problems(&Graph::build(&without_c)).is_empty());
    }

    /// A render / shell pair: `render` may use nothing of ours and only glam.
    fn render_and_shell(bands: &str) -> Tree {
        toy(
            &[
                ("lib.rs", "pub mod render;\npub mod shell;\n"),
                ("render/mod.rs", "pub mod bands;\npub struct DrawList;\n"),
                ("render/bands.rs", bands),
                ("shell/mod.rs", "pub mod window;\n"),
                ("shell/window.rs", "pub struct Window;\nuse crate::render::DrawList;\n"),
            ],
            "render: | glam\nshell: render | winit",
        )
    }

    #[test]
    fn a_forbidden_use_is_reported_with_file_line_and_rule() {
        let fine = render_and_shell("use glam::Vec3;\nuse super::DrawList;\n");
        assert_eq!(layer_problems(&fine, &Graph::build(&fine)), Vec::<String>::new());

        let tree = render_and_shell("use glam::Vec3;\n\nuse crate::shell::window;\n");
        let problems = layer_problems(&tree, &Graph::build(&tree));
        assert_eq!(problems.len(), 1, "{problems:?}");
        let p = &problems[0];
        assert!(p.contains("src/render/bands.rs (module `render`) uses src/shell/window.rs (module `shell`)"), "{p}");
        assert!(p.contains("`crate::shell::window` (line 3)"), "{p}");
        assert!(p.contains("ARCHITECTURE.md:6"), "{p}");
    }

    #[test]
    fn comments_doc_comments_and_strings_import_nothing() {
        let tree = render_and_shell(
            "//! See `crate::shell::window`.\n// use crate::shell::window;\n/// crate::shell::window::Window\n\
             /* use crate::shell::window; */\nconst S: &str = \"crate::shell::window::Window\";\n\
             const R: &str = r#\"use crate::shell::window;\"#;\nconst C: char = '\"';\nfn f<'a>(x: &'a u8) {}\n",
        );
        assert_eq!(layer_problems(&tree, &Graph::build(&tree)), Vec::<String>::new());
    }

    #[test]
    fn a_forbidden_path_written_in_code_or_test_code_is_reported() {
        let inline = render_and_shell("fn f() { let _ = crate::shell::window::Window; }\n");
        let problems = layer_problems(&inline, &Graph::build(&inline));
        assert!(problems.len() == 1 && problems[0].contains("`crate::shell::window::Window` (line 1)"), "{problems:?}");

        let test = render_and_shell("#[cfg(test)]\nmod tests {\n    use crate::shell::window::Window;\n}\n");
        let problems = layer_problems(&test, &Graph::build(&test));
        assert!(problems.len() == 1 && problems[0].contains("(line 3, test code)"), "{problems:?}");
    }

    #[test]
    fn an_external_crate_not_listed_is_reported_std_is_not() {
        let tree = render_and_shell(
            "use std::fmt;\nuse core::ops::Range;\nuse winit::window::Window;\nfn f() { rayon::join(|| (), || ()); }\n",
        );
        let problems = layer_problems(&tree, &Graph::build(&tree));
        assert_eq!(problems.len(), 2, "{problems:?}");
        assert!(problems[0].contains("names the external crate `rayon`: `rayon::join` (line 4)"), "{problems:?}");
        assert!(problems[1].contains("names the external crate `winit`: `winit::window::Window` (line 3)"));
        assert!(problems[1].contains("may name only [glam]"), "{problems:?}");
    }

    #[test]
    fn a_child_may_not_use_its_parent_but_the_parent_may_use_its_child() {
        let tree = toy(
            &[
                ("lib.rs", "pub mod render;\n"),
                ("render/mod.rs", "pub mod core;\npub use core::Mesh;\npub struct Options;\n"),
                ("render/core/mod.rs", "pub mod mesh;\npub use mesh::Mesh;\n"),
                ("render/core/mesh.rs", "pub struct Mesh;\nuse crate::render::Options;\n"),
            ],
            "render: | \nrender/core: | ",
        );
        let problems = layer_problems(&tree, &Graph::build(&tree));
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(problems[0].contains("src/render/core/mesh.rs (module `render/core`) uses src/render/mod.rs"));
    }

    #[test]
    fn a_file_without_a_rule_and_a_wrong_block_are_reported() {
        let tree = toy(
            &[("lib.rs", "pub mod game;\npub mod sound;\n"), ("game.rs", ""), ("sound/mod.rs", "")],
            "game: gaem | glam libmm\nrender: | \nbroken line",
        );
        let problems = layer_problems(&tree, &Graph::build(&tree));
        assert!(problems.iter().any(|p| p.contains("`broken line` is not `MODULE")), "{problems:?}");

        let tree = toy(
            &[("lib.rs", "pub mod game;\npub mod sound;\n"), ("game.rs", ""), ("sound/mod.rs", "")],
            "game: gaem | glam libmm\nrender: | ",
        );
        let problems = layer_problems(&tree, &Graph::build(&tree));
        let expected = [
            "`game` lists `gaem`, which has no rule of its own",
            "`game` lists `libmm`, which is not a dependency in Cargo.toml",
            "`render`: no file under src/ belongs to this rule",
            "src/sound/mod.rs belongs to no rule: add a line `sound: ... | ...`",
        ];
        for e in expected {
            assert!(problems.iter().any(|p| p.contains(e)), "missing {e:?} in {problems:?}");
        }
        assert_eq!(problems.len(), expected.len(), "{problems:?}");
    }

    #[test]
    fn a_path_into_our_crate_that_cannot_be_followed_is_reported() {
        let tree = render_and_shell("use crate::shell::nowhere::Window;\nuse super::DrawList::Variant;\n");
        let problems = layer_problems(&tree, &Graph::build(&tree));
        assert_eq!(problems, ["src/render/bands.rs:1: `crate::shell::nowhere::Window` reaches no module"]);
    }

    #[test]
    fn a_re_export_is_followed_to_the_file_that_defines_the_name() {
        let tree = toy(
            &[
                ("lib.rs", "pub mod render;\n"),
                (
                    "render/mod.rs",
                    "mod bands;\nmod camera;\nmod inner;\nmod options;\npub use options::DrawList;\npub use camera::*;\n",
                ),
                ("render/options.rs", "pub use super::inner::Deep as DrawList;\n"),
                ("render/inner.rs", "pub struct Deep;\n"),
                ("render/camera.rs", "pub struct Camera;\n"),
                ("render/bands.rs", "use super::DrawList;\nfn f(_: crate::render::Camera) {}\n"),
            ],
            "render: | ",
        );
        let arrows = arrows(&tree);
        assert!(arrows.contains(&"render/bands.rs -> render/inner.rs".to_string()), "{arrows:?}");
        assert!(arrows.contains(&"render/bands.rs -> render/camera.rs".to_string()), "{arrows:?}");
        assert!(!arrows.contains(&"render/bands.rs -> render/mod.rs".to_string()), "{arrows:?}");
    }

    #[test]
    fn a_use_group_resolves_every_member_and_inline_modules_are_their_file() {
        let tree = toy(
            &[
                ("lib.rs", "pub mod render;\n"),
                ("render/mod.rs", "pub mod a;\npub mod c;\npub mod e;\npub mod g;\n"),
                ("render/a.rs", "pub struct B;\n"),
                ("render/c.rs", "pub struct D;\npub mod slot {\n    pub const Q: usize = 1;\n}\n"),
                ("render/e.rs", "pub fn f() {}\n"),
                ("render/g/mod.rs", "pub mod h;\n"),
                ("render/g/h.rs", "pub struct H;\n"),
                (
                    "render/user.rs",
                    "pub(crate) use super::{a::B, c::{self, D}};\nuse self::super::g::{h::*};\n\
                     fn f() -> usize { super::e::f(); c::slot::Q }\n",
                ),
            ],
            "render: | ",
        );
        let arrows = arrows(&tree);
        for target in ["a.rs", "c.rs", "e.rs", "g/h.rs"] {
            assert!(arrows.contains(&format!("render/user.rs -> render/{target}")), "{target}: {arrows:?}");
        }
    }

    #[test]
    fn a_binary_folder_is_its_own_crate_and_names_the_library() {
        let tree = toy(
            &[
                ("lib.rs", "pub mod game;\n"),
                ("game.rs", "pub struct World;\n"),
                ("main.rs", "fn main() { toy_crate::game::World; }\n"),
                ("bin/gen/main.rs", "mod paint;\nmod track;\n"),
                ("bin/gen/paint.rs", "pub struct Canvas;\n"),
                ("bin/gen/track.rs", "use crate::paint::Canvas;\nuse toy_crate::game::World;\n"),
            ],
            "game: | \nbin/gen: | ",
        );
        let arrows = arrows(&tree);
        assert!(arrows.contains(&"bin/gen/track.rs -> bin/gen/paint.rs".to_string()), "{arrows:?}");
        assert!(arrows.contains(&"bin/gen/track.rs -> game.rs".to_string()), "{arrows:?}");
        assert!(arrows.contains(&"main.rs -> game.rs".to_string()), "{arrows:?}");
        let problems = layer_problems(&tree, &Graph::build(&tree));
        assert!(problems.len() == 1 && problems[0].contains("(module `bin/gen`) uses src/game.rs"), "{problems:?}");
    }

    /// A function of `lines` lines (the `fn` line to the closing brace).
    fn function(name: &str, lines: usize) -> String {
        format!("fn {name}() {{\n{}}}\n", "    let _ = 1;\n".repeat(lines - 2))
    }

    #[test]
    fn a_long_file_and_a_long_fn_are_reported_and_a_long_reason_exempts_the_fn() {
        let long_file = "// filler\n".repeat(MAX_FILE_LINES + 1);
        let short_file = "// filler\n".repeat(MAX_FILE_LINES);
        let fns = format!(
            "{}\n{}\n// long: one table, read top to bottom.\n/// Docs.\n#[inline]\n#[allow(\n    dead_code\n)]\n\
             pub(crate) fn {}\n",
            function("just_fits", MAX_FN_LINES),
            function("too_long", MAX_FN_LINES + 1),
            function("explained", MAX_FN_LINES + 20).trim_start_matches("fn "),
        );
        let tree = toy(&[("lib.rs", ""), ("long.rs", &long_file), ("short.rs", &short_file), ("fns.rs", &fns)], "");
        let problems = size_problems(&tree);
        assert_eq!(
            problems,
            [
                format!("src/fns.rs:{} fn too_long: 81 lines (at most 80, or a `// long: why` comment above it)", 82),
                "src/long.rs: 501 lines (at most 500)".to_string(),
            ]
        );
    }
}
