//! The requests, each computed on a snapshot (on a blocking thread, see
//! `requests::run`): positions in, analyzer call, LSP results out.

use hipop_analyzer::ide::FoldKind;
use hipop_analyzer::{Cancellable, TextRange};
use tower_lsp_server::ls_types as lsp;

use crate::convert;
use crate::session::{Snapshot, WorkspaceSnapshot};

pub(crate) fn document_symbols(snap: &Snapshot) -> Cancellable<Option<lsp::DocumentSymbolResponse>> {
    let file = snap.files().get(snap.file)?;
    let symbols = snap.analysis.document_symbols(snap.file)?;
    let symbols = symbols.iter().map(|s| convert::document_symbol(s, &file)).collect();
    Ok(Some(lsp::DocumentSymbolResponse::Nested(symbols)))
}

/// The analyzer's hover, and how the last plans use the name (planning on save).
pub(crate) fn hover(snap: &Snapshot, pos: lsp::Position) -> Cancellable<Option<lsp::Hover>> {
    let file = snap.files().get(snap.file)?;
    let offset = file.offset(pos);
    let mut hover = snap.analysis.hover(snap.file, offset.into())?;
    if let Some(planned) = crate::plan_features::hover_addition(snap, offset)? {
        let section = format!("**Last plan**\n\n{planned}");
        match &mut hover {
            Some(h) => h.markdown = format!("{}\n\n---\n\n{section}", h.markdown),
            None => {
                return Ok(Some(lsp::Hover {
                    contents: lsp::HoverContents::Markup(lsp::MarkupContent {
                        kind: lsp::MarkupKind::Markdown,
                        value: section,
                    }),
                    range: None,
                }));
            }
        }
    }
    Ok(hover.map(|h| convert::hover(h, &file)))
}

pub(crate) fn definition(
    snap: &Snapshot,
    pos: lsp::Position,
) -> Cancellable<Option<lsp::GotoDefinitionResponse>> {
    let mut files = snap.files();
    let offset = files.get(snap.file)?.offset(pos);
    let Some(target) = snap.analysis.goto_definition(snap.file, offset.into())? else { return Ok(None) };
    Ok(files.location(target.file, target.range)?.map(lsp::GotoDefinitionResponse::Scalar))
}

pub(crate) fn references(
    snap: &Snapshot,
    pos: lsp::Position,
    include_declaration: bool,
) -> Cancellable<Option<Vec<lsp::Location>>> {
    let mut files = snap.files();
    let offset = files.get(snap.file)?.offset(pos);
    let mut locations = Vec::new();
    for target in snap.analysis.references(snap.file, offset.into(), include_declaration)? {
        locations.extend(files.location(target.file, target.range)?);
    }
    Ok(Some(locations))
}

/// The occurrences in the document of the name at `pos`: its declaration
/// as a write, its uses as reads.
pub(crate) fn document_highlights(
    snap: &Snapshot,
    pos: lsp::Position,
) -> Cancellable<Option<Vec<lsp::DocumentHighlight>>> {
    let file = snap.files().get(snap.file)?;
    let highlights = snap.analysis.document_highlights(snap.file, file.offset(pos).into())?;
    let highlights = highlights
        .into_iter()
        .map(|h| lsp::DocumentHighlight {
            range: file.range(h.range),
            kind: Some(if h.declaration {
                lsp::DocumentHighlightKind::WRITE
            } else {
                lsp::DocumentHighlightKind::READ
            }),
        })
        .collect();
    Ok(Some(highlights))
}

/// The range and text of the name a rename at `pos` would change, or why
/// none would.
pub(crate) fn prepare_rename(
    snap: &Snapshot,
    pos: lsp::Position,
) -> Cancellable<Option<Result<lsp::PrepareRenameResponse, String>>> {
    let file = snap.files().get(snap.file)?;
    let answer = snap.analysis.prepare_rename(snap.file, file.offset(pos).into())?;
    Ok(Some(answer.map_err(|e| e.0).map(|(range, placeholder)| {
        lsp::PrepareRenameResponse::RangeWithPlaceholder { range: file.range(range), placeholder }
    })))
}

/// The edits of a rename at `pos` to `new_name`, in every file of the
/// domain, or why it is refused.
pub(crate) fn rename(
    snap: &Snapshot,
    pos: lsp::Position,
    new_name: &str,
) -> Cancellable<Option<Result<lsp::WorkspaceEdit, String>>> {
    let mut files = snap.files();
    let offset = files.get(snap.file)?.offset(pos);
    let targets = match snap.analysis.rename(snap.file, offset.into(), new_name)? {
        Ok(targets) => targets,
        Err(e) => return Ok(Some(Err(e.0))),
    };
    let edits: Vec<_> = targets.into_iter().map(|t| (t.file, t.range, new_name.to_string())).collect();
    let edit = convert::workspace_edit(&edits, &mut files)?;
    Ok(Some(edit.ok_or_else(|| "a file to change has no URI".to_string())))
}

/// Whole lines to fold: the lists and comment runs of the document, from
/// the line they start on to the line they end on.
pub(crate) fn folding_ranges(snap: &Snapshot) -> Cancellable<Option<Vec<lsp::FoldingRange>>> {
    let file = snap.files().get(snap.file)?;
    let mut out: Vec<lsp::FoldingRange> = Vec::new();
    for fold in snap.analysis.folding_ranges(snap.file)? {
        let range = file.range(fold.range);
        let (start, end) = (range.start.line, range.end.line);
        // Two lists opening on one line and closing on one (`(and (or`…
        // `))`) fold the same lines: once is enough.
        if end <= start || out.last().is_some_and(|f| f.start_line == start && f.end_line == end) {
            continue;
        }
        out.push(lsp::FoldingRange {
            start_line: start,
            end_line: end,
            kind: match fold.kind {
                FoldKind::Comment => Some(lsp::FoldingRangeKind::Comment),
                FoldKind::List => None,
            },
            ..lsp::FoldingRange::default()
        });
    }
    Ok(Some(out))
}

/// The quick fixes of the diagnostics that touch `range`.
pub(crate) fn code_actions(
    snap: &Snapshot,
    range: lsp::Range,
) -> Cancellable<Option<lsp::CodeActionResponse>> {
    let mut files = snap.files();
    let file = files.get(snap.file)?;
    let (a, b) = (file.offset(range.start), file.offset(range.end));
    let wanted = TextRange::new(a.min(b).into(), a.max(b).into());
    let mut actions = Vec::new();
    for d in snap.analysis.diagnostics(snap.file)? {
        if d.file == snap.file
            && d.range.intersect(wanted).is_some()
            && let Some(action) = convert::quick_fix(&d, &mut files)?
        {
            actions.push(lsp::CodeActionOrCommand::CodeAction(action));
        }
    }
    // Then the analyzer's own: an undeclared predicate declared.
    for action in snap.analysis.code_actions(snap.file, wanted)? {
        let Some(edit) = convert::workspace_edit(&action.edits, &mut files)? else { continue };
        actions.push(lsp::CodeActionOrCommand::CodeAction(lsp::CodeAction {
            title: action.title,
            kind: Some(lsp::CodeActionKind::QUICKFIX),
            edit: Some(edit),
            ..lsp::CodeAction::default()
        }));
    }
    Ok(Some(actions))
}

/// The document formatted (`hipop fmt`'s layout): one edit replacing the
/// lines that change, none when it is formatted already; no answer for a
/// document with a syntax error, or a plan.
pub(crate) fn formatting(snap: &Snapshot) -> Cancellable<Option<Vec<lsp::TextEdit>>> {
    let file = snap.files().get(snap.file)?;
    let Ok(formatted) = snap.analysis.format(snap.file)? else { return Ok(None) };
    let (old, new) = (file.text.as_bytes(), formatted.as_bytes());
    if old == new {
        return Ok(Some(Vec::new()));
    }
    // Whole lines: the common prefix up to a line start, the common suffix from one.
    let common = old.iter().zip(new).take_while(|(a, b)| a == b).count();
    let start = old[..common].iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let limit = (old.len() - start).min(new.len() - start);
    let same_end = old.iter().rev().zip(new.iter().rev()).take(limit).take_while(|(a, b)| a == b).count();
    let suffix = old.len() - same_end;
    let tail = if suffix == 0 || old[suffix - 1] == b'\n' {
        same_end
    } else {
        old[suffix..].iter().position(|&b| b == b'\n').map_or(0, |i| same_end - i - 1)
    };
    let (old_end, new_end) = (old.len() - tail, new.len() - tail);
    let range = TextRange::new((start as u32).into(), (old_end as u32).into());
    Ok(Some(vec![lsp::TextEdit::new(file.range(range), formatted[start..new_end].to_string())]))
}

/// The declarations of the workspace whose names match `query`.
pub(crate) fn workspace_symbols(
    snap: &WorkspaceSnapshot,
    query: &str,
) -> Cancellable<Option<lsp::WorkspaceSymbolResponse>> {
    let mut files = snap.files();
    let mut symbols = Vec::new();
    for s in snap.analysis.workspace_symbols(query)? {
        if let Some(location) = files.location(s.file, s.range)? {
            symbols.push(convert::symbol_information(s, location));
        }
    }
    Ok(Some(lsp::WorkspaceSymbolResponse::Flat(symbols)))
}

/// The completions at `pos`, each replacing the word being typed; snippets
/// as plain text for a client without snippets.
pub(crate) fn completions(
    snap: &Snapshot,
    pos: lsp::Position,
) -> Cancellable<Option<lsp::CompletionResponse>> {
    let file = snap.files().get(snap.file)?;
    let items = snap.analysis.completions(snap.file, file.offset(pos).into())?;
    let items = items.into_iter().map(|c| convert::completion_item(c, &file, snap.snippets)).collect();
    Ok(Some(lsp::CompletionResponse::Array(items)))
}

/// The semantic tokens of the document, or of `range` of it.
pub(crate) fn semantic_tokens(
    snap: &Snapshot,
    range: Option<lsp::Range>,
) -> Cancellable<Option<lsp::SemanticTokens>> {
    let file = snap.files().get(snap.file)?;
    let tokens = snap.analysis.semantic_tokens(snap.file)?;
    let within = range.map(|r| {
        let (a, b) = (file.offset(r.start), file.offset(r.end));
        TextRange::new(a.min(b).into(), a.max(b).into())
    });
    let data = convert::semantic_tokens(&tokens, &file, within);
    Ok(Some(lsp::SemanticTokens { result_id: None, data }))
}
