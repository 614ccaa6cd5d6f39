-- Driven by lsp/tests/neovim.rs, once editors/neovim/hipop.lua (the config a
-- user loads) is loaded: opens files as a user would and writes what Neovim
-- got to $HIPOP_OUT, one fact per line. Neovim 0.7 API only.
--   $HIPOP_FILE     a domain: its file type, client, diagnostics and a hover
--                   at $HIPOP_HOVER_LINE:$HIPOP_HOVER_CHAR;
--   $HIPOP_PLAN     a plan beside its problem: its file type and diagnostics;
--   $HIPOP_PROBLEM  a problem beside $HIPOP_DOMAIN: its diagnostics before and
--                   after the domain is rewritten on disk (by this script, not
--                   through Neovim, which does not watch files for servers).
local lines = {}
local function say(fmt, ...) table.insert(lines, string.format(fmt, ...)) end

-- Counts the publications per URI, to know when the server has spoken.
local published = {}
local default_handler = vim.lsp.handlers['textDocument/publishDiagnostics']
vim.lsp.handlers['textDocument/publishDiagnostics'] = function(err, result, ctx, config)
  if result then
    published[result.uri] = (published[result.uri] or 0) + 1
  end
  return default_handler(err, result, ctx, config)
end

local function open(path)
  vim.cmd('edit ' .. vim.fn.fnameescape(path))
  local bufnr = vim.api.nvim_get_current_buf()
  -- Attached at once, listed once initialized.
  vim.wait(10000, function() return next(vim.lsp.buf_get_clients(bufnr)) ~= nil end, 20)
  local clients = vim.lsp.buf_get_clients(bufnr)
  local names = {}
  for _, client in pairs(clients) do
    table.insert(names, client.name .. ' at ' .. vim.fn.fnamemodify(client.config.root_dir, ':t'))
  end
  say('open %s: filetype %s, clients %s', vim.fn.fnamemodify(path, ':t'), vim.bo[bufnr].filetype,
    table.concat(names, ', '))
  return bufnr
end

local function report_diagnostics(bufnr, what)
  local diags = vim.diagnostic.get(bufnr)
  table.sort(diags, function(a, b) return a.lnum < b.lnum or (a.lnum == b.lnum and a.col < b.col) end)
  for _, d in ipairs(diags) do
    -- Columns are byte columns: Neovim converted them from the UTF-16 the server sent.
    say('%s %d:%d-%d:%d %s %s', what, d.lnum, d.col, d.end_lnum, d.end_col, tostring(d.code),
      vim.split(d.message, '\n', true)[1])
  end
end

local function wait_for_diagnostics(bufnr, what)
  if not vim.wait(30000, function() return #vim.diagnostic.get(bufnr) > 0 end, 50) then
    say('TIMEOUT waiting for the diagnostics of %s', what)
  end
end

local function run()
  -- A domain: diagnostics, then a hover.
  local bufnr = open(os.getenv('HIPOP_FILE'))
  wait_for_diagnostics(bufnr, 'the domain')
  report_diagnostics(bufnr, 'diagnostic')
  local params = {
    textDocument = { uri = vim.uri_from_bufnr(bufnr) },
    position = { line = tonumber(os.getenv('HIPOP_HOVER_LINE')), character = tonumber(os.getenv('HIPOP_HOVER_CHAR')) },
  }
  local responses = vim.lsp.buf_request_sync(bufnr, 'textDocument/hover', params, 10000) or {}
  for _, response in pairs(responses) do
    if response.result then
      for line in vim.gsplit(response.result.contents.value or '', '\n', true) do
        say('hover %s', line)
      end
    else
      say('hover error %s', vim.inspect(response.err))
    end
  end

  -- A plan: validated against the problem beside it.
  bufnr = open(os.getenv('HIPOP_PLAN'))
  wait_for_diagnostics(bufnr, 'the plan')
  report_diagnostics(bufnr, 'plan')

  -- A problem whose domain changes on disk behind Neovim's back.
  bufnr = open(os.getenv('HIPOP_PROBLEM'))
  local uri = vim.uri_from_bufnr(bufnr)
  if not vim.wait(30000, function() return (published[uri] or 0) > 0 end, 50) then
    say('TIMEOUT waiting for the first diagnostics of the problem')
  end
  say('problem before: %d diagnostics', #vim.diagnostic.get(bufnr))
  local domain = os.getenv('HIPOP_DOMAIN')
  local file = assert(io.open(domain, 'r'))
  local text = file:read('*a')
  file:close()
  file = assert(io.open(domain, 'w'))
  file:write((text:gsub('%(held %?b', '(grasped ?b')))
  file:close()
  wait_for_diagnostics(bufnr, 'the problem after the domain changed on disk')
  report_diagnostics(bufnr, 'problem after')

  for _, client in pairs(vim.lsp.get_active_clients()) do
    client.stop()
  end
  vim.wait(5000, function() return #vim.lsp.get_active_clients() == 0 end, 50)
end

local ok, err = pcall(run)
if not ok then
  say('ERROR %s', tostring(err))
end
local out = assert(io.open(os.getenv('HIPOP_OUT'), 'w'))
out:write(table.concat(lines, '\n') .. '\n')
out:close()
vim.cmd('qa!')
