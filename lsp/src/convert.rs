//! Every conversion between the analyzer's plain data (byte offsets) and
//! `ls_types`. Keeping them in one module confines the LSP type library, whose
//! 0.0.x releases may break, to one place.
//!
//! Results can point into other files than the one asked about (a problem's
//! diagnostic relates to its domain; references span the domain and its
//! problems), so ranges are converted with the text of the file they belong
//! to, looked up through [`Files`].

use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;
use std::sync::Arc;

use hipop_analyzer::{Analysis, Cancellable, Severity, SourceFile, TextRange, codes, ide};
use tower_lsp_server::ls_types as lsp;

use crate::line_index::{Encoding, LineCol, LineIndex};

/// The byte offset of an LSP position in `text`, clamped.
pub(crate) fn offset(index: &LineIndex, text: &str, pos: lsp::Position, enc: Encoding) -> u32 {
    index.offset(text, LineCol { line: pos.line, col: pos.character }, enc)
}

/// The LSP position of a byte offset in `text`.
pub(crate) fn position(index: &LineIndex, text: &str, offset: u32, enc: Encoding) -> lsp::Position {
    let lc = index.line_col(text, offset, enc);
    lsp::Position::new(lc.line, lc.col)
}

pub(crate) fn encoding_kind(enc: Encoding) -> lsp::PositionEncodingKind {
    match enc {
        Encoding::Utf8 => lsp::PositionEncodingKind::UTF8,
        Encoding::Utf16 => lsp::PositionEncodingKind::UTF16,
        Encoding::Utf32 => lsp::PositionEncodingKind::UTF32,
    }
}

/// The encoding to use with a client: UTF-8 when offered, because it is the
/// analyzer's own unit, else UTF-16, which every client must support (UTF-32
/// only for a client that offers it and not UTF-16). Offers come from LSP
/// 3.17's `general.positionEncodings`, or else from clangd's older
/// `offsetEncoding` extension.
pub(crate) fn negotiate_encoding(caps: &lsp::ClientCapabilities) -> Encoding {
    let standard = caps.general.as_ref().and_then(|g| g.position_encodings.as_deref());
    let offered: Vec<&str> = match (standard, &caps.offset_encoding) {
        (Some(offered), _) => offered.iter().map(|e| e.as_str()).collect(),
        (None, Some(offered)) => offered.iter().map(String::as_str).collect(),
        (None, None) => Vec::new(),
    };
    if offered.contains(&"utf-8") {
        Encoding::Utf8
    } else if offered.contains(&"utf-32") && !offered.contains(&"utf-16") {
        Encoding::Utf32
    } else {
        Encoding::Utf16
    }
}

/// The analyzer's name for a document: its path for a `file:` URI, else the URI itself.
pub(crate) fn file_key(uri: &lsp::Uri) -> String {
    if uri.as_str().starts_with("file:")
        && let Some(path) = uri.to_file_path()
    {
        return path.to_string_lossy().into_owned();
    }
    uri.as_str().to_string()
}

/// The URI of a file the analyzer knows by `key`: the client's own spelling
/// when the document is open, else one built from the path.
pub(crate) fn key_uri(key: &str, open: &HashMap<String, lsp::Uri>) -> Option<lsp::Uri> {
    if let Some(uri) = open.get(key) {
        return Some(uri.clone());
    }
    if Path::new(key).is_absolute() { lsp::Uri::from_file_path(key) } else { key.parse().ok() }
}

/// One file's text and line index, as seen by a snapshot.
pub(crate) struct FileInfo {
    pub uri: Option<lsp::Uri>,
    pub text: Arc<str>,
    pub index: Arc<LineIndex>,
    pub enc: Encoding,
}

impl FileInfo {
    pub(crate) fn offset(&self, pos: lsp::Position) -> u32 {
        offset(&self.index, &self.text, pos, self.enc)
    }

    pub(crate) fn range(&self, range: TextRange) -> lsp::Range {
        lsp::Range::new(
            position(&self.index, &self.text, range.start().into(), self.enc),
            position(&self.index, &self.text, range.end().into(), self.enc),
        )
    }

    fn location(&self, range: TextRange) -> Option<lsp::Location> {
        Some(lsp::Location::new(self.uri.clone()?, self.range(range)))
    }
}

/// The files a request's results point into, each indexed once.
pub(crate) struct Files<'a> {
    analysis: &'a Analysis,
    open: &'a HashMap<String, lsp::Uri>,
    enc: Encoding,
    cache: HashMap<SourceFile, Rc<FileInfo>>,
    /// The line indexes the open documents keep up to date (indexing a 5 MB
    /// file again for every publication would dominate the latency).
    indexes: &'a HashMap<SourceFile, Arc<LineIndex>>,
}

impl<'a> Files<'a> {
    pub(crate) fn new(
        analysis: &'a Analysis,
        open: &'a HashMap<String, lsp::Uri>,
        enc: Encoding,
        indexes: &'a HashMap<SourceFile, Arc<LineIndex>>,
    ) -> Files<'a> {
        Files { analysis, open, enc, cache: HashMap::new(), indexes }
    }

    pub(crate) fn get(&mut self, file: SourceFile) -> Cancellable<Rc<FileInfo>> {
        if let Some(info) = self.cache.get(&file) {
            return Ok(info.clone());
        }
        let text = self.analysis.file_text(file)?;
        let uri = key_uri(&self.analysis.file_path(file)?, self.open);
        let index = self.indexes.get(&file).cloned().unwrap_or_else(|| Arc::new(LineIndex::new(&text)));
        let info = Rc::new(FileInfo { uri, index, text, enc: self.enc });
        self.cache.insert(file, info.clone());
        Ok(info)
    }

    pub(crate) fn location(
        &mut self,
        file: SourceFile,
        range: TextRange,
    ) -> Cancellable<Option<lsp::Location>> {
        Ok(self.get(file)?.location(range))
    }
}

fn severity(s: Severity) -> lsp::DiagnosticSeverity {
    match s {
        Severity::Error => lsp::DiagnosticSeverity::ERROR,
        Severity::Warning => lsp::DiagnosticSeverity::WARNING,
        Severity::Info => lsp::DiagnosticSeverity::INFORMATION,
    }
}

/// A diagnostic with its code (`E0102`), severity and related locations.
pub(crate) fn diagnostic(
    d: &hipop_analyzer::Diagnostic,
    files: &mut Files<'_>,
) -> Cancellable<lsp::Diagnostic> {
    let mut related = Vec::new();
    for r in &d.related {
        if let Some(location) = files.location(r.file, r.range)? {
            related.push(lsp::DiagnosticRelatedInformation { location, message: r.message.clone() });
        }
    }
    // Compared by id: a `const` reference is not guaranteed one address.
    let unused = d.code.id == codes::UNUSED.id;
    Ok(lsp::Diagnostic {
        range: files.get(d.file)?.range(d.range),
        severity: Some(severity(d.severity)),
        code: Some(lsp::NumberOrString::String(d.code.id.to_string())),
        code_description: None,
        source: Some("hipop".to_string()),
        message: match &d.fix {
            // Advice without an edit (a repair hint): in the message, as the CLI's `help:`.
            Some(f) if f.edits.is_empty() => format!("{}\nhelp: {}", d.message, f.message),
            _ => d.message.clone(),
        },
        related_information: (!related.is_empty()).then_some(related),
        tags: unused.then(|| vec![lsp::DiagnosticTag::UNNECESSARY]),
        data: None,
    })
}

/// The quick fix of a diagnostic, if it has one with edits whose files all
/// have URIs (a fix without edits is advice, shown in the message only).
pub(crate) fn quick_fix(
    d: &hipop_analyzer::Diagnostic,
    files: &mut Files<'_>,
) -> Cancellable<Option<lsp::CodeAction>> {
    let Some(fix) = d.fix.as_ref().filter(|f| !f.edits.is_empty()) else { return Ok(None) };
    let Some(edit) = workspace_edit(&fix.edits, files)? else { return Ok(None) };
    Ok(Some(lsp::CodeAction {
        title: fix.message.clone(),
        kind: Some(lsp::CodeActionKind::QUICKFIX),
        diagnostics: Some(vec![diagnostic(d, files)?]),
        edit: Some(edit),
        is_preferred: Some(true),
        ..lsp::CodeAction::default()
    }))
}

/// The analyzer's edits (file, range, text) as a workspace edit; `None` when
/// a file has no URI to name it by.
pub(crate) fn workspace_edit(
    edits: &[(SourceFile, TextRange, String)],
    files: &mut Files<'_>,
) -> Cancellable<Option<lsp::WorkspaceEdit>> {
    let mut changes: HashMap<lsp::Uri, Vec<lsp::TextEdit>> = HashMap::new();
    for (file, range, text) in edits {
        let info = files.get(*file)?;
        let Some(uri) = info.uri.clone() else { return Ok(None) };
        changes.entry(uri).or_default().push(lsp::TextEdit::new(info.range(*range), text.clone()));
    }
    Ok(Some(lsp::WorkspaceEdit { changes: Some(changes), ..lsp::WorkspaceEdit::default() }))
}

/// Symbol kinds: a predicate is a boolean state variable, a function a numeric
/// one, an action is what executes, a task is abstract (methods implement it).
fn symbol_kind(kind: ide::SymbolKind) -> lsp::SymbolKind {
    use ide::SymbolKind as K;
    match kind {
        K::Domain => lsp::SymbolKind::MODULE,
        K::Problem => lsp::SymbolKind::PACKAGE,
        K::Section => lsp::SymbolKind::NAMESPACE,
        K::Type => lsp::SymbolKind::CLASS,
        K::Constant => lsp::SymbolKind::CONSTANT,
        K::Object => lsp::SymbolKind::OBJECT,
        K::Predicate => lsp::SymbolKind::BOOLEAN,
        K::Function => lsp::SymbolKind::NUMBER,
        K::Action => lsp::SymbolKind::FUNCTION,
        K::Task => lsp::SymbolKind::INTERFACE,
        K::Method => lsp::SymbolKind::METHOD,
    }
}

/// An outline entry. Clients reject a selection range outside the full range,
/// so such a selection is replaced by the range's start.
pub(crate) fn document_symbol(s: &ide::DocumentSymbol, file: &FileInfo) -> lsp::DocumentSymbol {
    let selection = if s.range.contains_range(s.selection_range) {
        s.selection_range
    } else {
        TextRange::empty(s.range.start())
    };
    let children: Vec<lsp::DocumentSymbol> = s.children.iter().map(|c| document_symbol(c, file)).collect();
    #[expect(deprecated, reason = "`deprecated` has no default and must be spelled out")]
    lsp::DocumentSymbol {
        name: if s.name.is_empty() { "?".to_string() } else { s.name.clone() },
        detail: s.detail.clone(),
        kind: symbol_kind(s.kind),
        tags: None,
        deprecated: None,
        range: file.range(s.range),
        selection_range: file.range(selection),
        children: (!children.is_empty()).then_some(children),
    }
}

/// A symbol of the workspace, located at its name.
pub(crate) fn symbol_information(s: ide::WorkspaceSymbol, location: lsp::Location) -> lsp::SymbolInformation {
    #[expect(deprecated, reason = "`deprecated` has no default and must be spelled out")]
    lsp::SymbolInformation {
        name: if s.name.is_empty() { "?".to_string() } else { s.name },
        kind: symbol_kind(s.kind),
        tags: None,
        deprecated: None,
        location,
        container_name: s.container,
    }
}

pub(crate) fn hover(h: ide::HoverResult, file: &FileInfo) -> lsp::Hover {
    lsp::Hover {
        contents: lsp::HoverContents::Markup(lsp::MarkupContent {
            kind: lsp::MarkupKind::Markdown,
            value: h.markdown,
        }),
        range: Some(file.range(h.range)),
    }
}

/// A completion: its text replaces the word being typed. A snippet is sent
/// as one only to a client that accepts them, and as its text with the
/// placeholders' defaults otherwise.
pub(crate) fn completion_item(c: ide::Completion, file: &FileInfo, snippets: bool) -> lsp::CompletionItem {
    use ide::CompletionKind as K;
    let kind = match c.kind {
        K::Keyword => lsp::CompletionItemKind::KEYWORD,
        K::Requirement => lsp::CompletionItemKind::ENUM_MEMBER,
        K::Type => lsp::CompletionItemKind::CLASS,
        K::Predicate => lsp::CompletionItemKind::INTERFACE,
        K::Function => lsp::CompletionItemKind::FUNCTION,
        K::Action => lsp::CompletionItemKind::METHOD,
        K::Task => lsp::CompletionItemKind::EVENT,
        K::Constant => lsp::CompletionItemKind::CONSTANT,
        K::Object => lsp::CompletionItemKind::VALUE,
        K::Variable => lsp::CompletionItemKind::VARIABLE,
        K::Domain => lsp::CompletionItemKind::MODULE,
        K::Snippet => lsp::CompletionItemKind::SNIPPET,
    };
    let (text, format) = match (c.snippet, snippets) {
        (true, true) => (c.insert, lsp::InsertTextFormat::SNIPPET),
        (true, false) => (snippet_text(&c.insert), lsp::InsertTextFormat::PLAIN_TEXT),
        (false, _) => (c.insert, lsp::InsertTextFormat::PLAIN_TEXT),
    };
    lsp::CompletionItem {
        label: c.label,
        kind: Some(kind),
        detail: c.detail,
        sort_text: Some(c.sort),
        // Filtered on the word it replaces, `:` and `?` included.
        filter_text: None,
        insert_text_format: Some(format),
        text_edit: Some(lsp::CompletionTextEdit::Edit(lsp::TextEdit {
            range: file.range(c.range),
            new_text: text,
        })),
        ..lsp::CompletionItem::default()
    }
}

/// The text of a snippet without its tab stops: `${1:name}` becomes `name`,
/// `$0` and `${2}` nothing.
pub(crate) fn snippet_text(snippet: &str) -> String {
    let mut out = String::with_capacity(snippet.len());
    let mut rest = snippet;
    while let Some(i) = rest.find('$') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        if let Some(inner) = after.strip_prefix('{')
            && let Some(end) = inner.find('}')
        {
            let body = &inner[..end];
            if let Some((_, default)) = body.split_once(':') {
                out.push_str(default);
            }
            rest = &inner[end + 1..];
        } else {
            let digits = after.find(|c: char| !c.is_ascii_digit()).unwrap_or(after.len());
            if digits == 0 {
                out.push('$');
            }
            rest = &after[digits..];
        }
    }
    out.push_str(rest);
    out
}

/// The semantic token types the server uses, standard ones so that default
/// themes colour them; a token's type is its index here.
pub(crate) const TOKEN_TYPES: &[lsp::SemanticTokenType] = &[
    lsp::SemanticTokenType::KEYWORD,
    lsp::SemanticTokenType::OPERATOR,
    lsp::SemanticTokenType::COMMENT,
    lsp::SemanticTokenType::NUMBER,
    lsp::SemanticTokenType::TYPE,
    lsp::SemanticTokenType::FUNCTION,
    lsp::SemanticTokenType::PROPERTY,
    lsp::SemanticTokenType::METHOD,
    lsp::SemanticTokenType::ENUM_MEMBER,
    lsp::SemanticTokenType::PARAMETER,
    lsp::SemanticTokenType::VARIABLE,
    lsp::SemanticTokenType::MACRO,
    lsp::SemanticTokenType::NAMESPACE,
];

/// The modifiers, bit `i` for the `i`th.
pub(crate) const TOKEN_MODIFIERS: &[lsp::SemanticTokenModifier] = &[
    lsp::SemanticTokenModifier::DECLARATION,
    lsp::SemanticTokenModifier::READONLY,
    lsp::SemanticTokenModifier::ABSTRACT,
    lsp::SemanticTokenModifier::DEFAULT_LIBRARY,
];

/// A highlighted token's type and modifiers: a predicate is a function, a
/// numeric function a property, an action a method and a task an abstract
/// one, an object an enum member (a constant a read-only one), a
/// requirement a macro, a domain's name a namespace.
fn token_type(t: &ide::HighlightToken) -> (u32, u32) {
    use ide::HighlightKind as K;
    let ty = |t: lsp::SemanticTokenType| TOKEN_TYPES.iter().position(|x| *x == t).unwrap_or(0) as u32;
    let bit = |m: lsp::SemanticTokenModifier| 1 << TOKEN_MODIFIERS.iter().position(|x| *x == m).unwrap_or(0);
    let (kind, mut modifiers) = match t.kind {
        K::Keyword => (lsp::SemanticTokenType::KEYWORD, 0),
        K::Operator => (lsp::SemanticTokenType::OPERATOR, 0),
        K::Comment => (lsp::SemanticTokenType::COMMENT, 0),
        K::Number => (lsp::SemanticTokenType::NUMBER, 0),
        K::Type => (lsp::SemanticTokenType::TYPE, 0),
        K::Predicate => (lsp::SemanticTokenType::FUNCTION, 0),
        K::Function => (lsp::SemanticTokenType::PROPERTY, 0),
        K::Action | K::Method => (lsp::SemanticTokenType::METHOD, 0),
        K::Task => (lsp::SemanticTokenType::METHOD, bit(lsp::SemanticTokenModifier::ABSTRACT)),
        K::Constant => (lsp::SemanticTokenType::ENUM_MEMBER, bit(lsp::SemanticTokenModifier::READONLY)),
        K::Object => (lsp::SemanticTokenType::ENUM_MEMBER, 0),
        K::Parameter => (lsp::SemanticTokenType::PARAMETER, 0),
        K::Variable => (lsp::SemanticTokenType::VARIABLE, 0),
        K::SubtaskId => (lsp::SemanticTokenType::VARIABLE, bit(lsp::SemanticTokenModifier::READONLY)),
        K::Requirement => (lsp::SemanticTokenType::MACRO, 0),
        K::UnitName => (lsp::SemanticTokenType::NAMESPACE, 0),
    };
    if t.declaration {
        modifiers |= bit(lsp::SemanticTokenModifier::DECLARATION);
    }
    if t.builtin {
        modifiers |= bit(lsp::SemanticTokenModifier::DEFAULT_LIBRARY);
    }
    (ty(kind), modifiers)
}

/// The tokens in `within`, relative to the one before (LSP's encoding), in
/// the negotiated unit. A token never spans lines (an atom or a comment);
/// one that would is left out.
pub(crate) fn semantic_tokens(
    tokens: &[ide::HighlightToken],
    file: &FileInfo,
    within: Option<TextRange>,
) -> Vec<lsp::SemanticToken> {
    let mut out = Vec::with_capacity(tokens.len());
    let (mut line, mut start) = (0, 0);
    for t in tokens {
        if within.is_some_and(|w| w.intersect(t.range).is_none_or(|i| i.is_empty() && !t.range.is_empty())) {
            continue;
        }
        let range = file.range(t.range);
        if range.start.line != range.end.line || range.end.character <= range.start.character {
            continue;
        }
        let (token_type, token_modifiers_bitset) = token_type(t);
        let delta_line = range.start.line - line;
        let delta_start = if delta_line == 0 { range.start.character - start } else { range.start.character };
        out.push(lsp::SemanticToken {
            delta_line,
            delta_start,
            length: range.end.character - range.start.character,
            token_type,
            token_modifiers_bitset,
        });
        (line, start) = (range.start.line, range.start.character);
    }
    out
}

#[cfg(test)]
mod tests {
    use hipop_analyzer::AnalysisHost;
    use tower_lsp_server::ls_types::{ClientCapabilities, GeneralClientCapabilities, Position, Range};

    use super::*;

    fn caps(standard: Option<&[&'static str]>, clangd: Option<&[&str]>) -> ClientCapabilities {
        ClientCapabilities {
            general: standard.map(|e| GeneralClientCapabilities {
                position_encodings: Some(e.iter().map(|&k| lsp::PositionEncodingKind::from(k)).collect()),
                ..GeneralClientCapabilities::default()
            }),
            offset_encoding: clangd.map(|e| e.iter().map(|k| k.to_string()).collect()),
            ..ClientCapabilities::default()
        }
    }

    #[test]
    fn negotiation_prefers_utf8_then_utf16() {
        assert_eq!(negotiate_encoding(&caps(None, None)), Encoding::Utf16);
        assert_eq!(negotiate_encoding(&caps(Some(&["utf-16", "utf-8"]), None)), Encoding::Utf8);
        assert_eq!(negotiate_encoding(&caps(Some(&["utf-32", "utf-16"]), None)), Encoding::Utf16);
        assert_eq!(negotiate_encoding(&caps(Some(&["utf-32"]), None)), Encoding::Utf32);
        assert_eq!(negotiate_encoding(&caps(None, Some(&["utf-8", "utf-16"]))), Encoding::Utf8);
        // The standard field wins over the extension.
        assert_eq!(negotiate_encoding(&caps(Some(&["utf-16"]), Some(&["utf-8"]))), Encoding::Utf16);
    }

    #[test]
    fn keys_and_uris_round_trip() {
        let uri: lsp::Uri = "file:///tmp/a%20b/domain.pddl".parse().unwrap();
        assert_eq!(file_key(&uri), "/tmp/a b/domain.pddl");
        let untitled: lsp::Uri = "untitled:Untitled-1".parse().unwrap();
        assert_eq!(file_key(&untitled), "untitled:Untitled-1");
        let none = HashMap::new();
        assert_eq!(key_uri("untitled:Untitled-1", &none), Some(untitled));
        assert_eq!(key_uri("/tmp/a b/domain.pddl", &none).unwrap().as_str(), "file:///tmp/a%20b/domain.pddl");
        let open = HashMap::from([("/x.pddl".to_string(), "file:///x.pddl?spelled".parse().unwrap())]);
        assert_eq!(key_uri("/x.pddl", &open).unwrap().as_str(), "file:///x.pddl?spelled");
    }

    const DOMAIN: &str = "(define (domain d)\n  (:predicates (p ?x)))\n";

    /// A problem's diagnostic relates to its domain: converted with the domain's text.
    #[test]
    fn related_information_points_into_the_other_file() {
        let mut host = AnalysisHost::new();
        host.set_file_text("/w/domain.pddl", DOMAIN);
        let problem = "(define (problem q) (:domain d)\n  ; été 😀\n  (:objects a) (:init (p a a)))\n";
        let file = host.set_file_text("/w/problem.pddl", problem);
        let analysis = host.analysis();
        let diags = analysis.diagnostics(file).unwrap();
        let arity = diags.iter().find(|d| d.code.id == "E0110").expect("an arity error");
        let open = HashMap::new();
        let no_indexes = HashMap::new();
        let mut files = Files::new(&analysis, &open, Encoding::Utf16, &no_indexes);
        let converted = diagnostic(arity, &mut files).unwrap();
        assert_eq!(converted.code, Some(lsp::NumberOrString::String("E0110".into())));
        assert_eq!(converted.severity, Some(lsp::DiagnosticSeverity::ERROR));
        assert_eq!(converted.source.as_deref(), Some("hipop"));
        assert_eq!(converted.range.start.line, 2);
        let related = converted.related_information.expect("related information");
        assert_eq!(related[0].location.uri.as_str(), "file:///w/domain.pddl");
        assert_eq!(related[0].location.range, Range::new(Position::new(1, 16), Position::new(1, 17)));
    }

    #[test]
    fn ranges_are_converted_in_the_negotiated_encoding() {
        let mut host = AnalysisHost::new();
        let text = "(define (domain d) (:predicates (p ?x))\n (:action a :parameters (?x)\n :precondition (and (é ?x) (p ?x))))\n";
        let file = host.set_file_text("/w/d.pddl", text);
        let analysis = host.analysis();
        let diags = analysis.diagnostics(file).unwrap();
        let undefined = diags.iter().find(|d| d.code.id == "E0102").expect("undefined predicate");
        let open = HashMap::new();
        let columns = |enc| {
            let r =
                diagnostic(undefined, &mut Files::new(&analysis, &open, enc, &HashMap::new())).unwrap().range;
            (r.start.line, r.start.character, r.end.character)
        };
        // `é` is one UTF-16 unit and code point, two UTF-8 bytes.
        assert_eq!(columns(Encoding::Utf16), (2, 21, 22));
        assert_eq!(columns(Encoding::Utf32), (2, 21, 22));
        assert_eq!(columns(Encoding::Utf8), (2, 21, 23));
    }

    #[test]
    fn a_snippet_without_its_tab_stops() {
        assert_eq!(snippet_text("(:task ${1:name} :parameters (${2}))$0"), "(:task name :parameters ())");
        assert_eq!(snippet_text("costs $5 and ${x"), "costs  and ${x");
        assert_eq!(snippet_text("a $ b"), "a $ b");
    }
}
