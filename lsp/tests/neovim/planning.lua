-- Driven by lsp/tests/neovim.rs, once editors/neovim/hipop.lua is loaded:
-- plans a problem on save and writes what Neovim shows to $HIPOP_OUT, one
-- fact per line. Neovim 0.7 API (the inlay hints through the virtual text
-- hipop.lua draws before 0.10, or Neovim's own from 0.10 on).
--   $HIPOP_PROBLEM  a problem beside its domain (a copy: it is rewritten)
--   $HIPOP_SURVEILLANCE  a copy of the surveillance sample's problem
local lines = {}
local function say(fmt, ...) table.insert(lines, string.format(fmt, ...)) end

-- Times vary from run to run: `0.01 s` becomes `T s`.
local function masked(text) return (text:gsub('%d+%.%d+ s', 'T s')) end

local planned = nil
vim.api.nvim_create_autocmd('User', { pattern = 'HipopPlanned', callback = function() planned = true end })

local function hints(bufnr)
  local out = {}
  if vim.lsp.inlay_hint then
    local params = {
      textDocument = { uri = vim.uri_from_bufnr(bufnr) },
      range = { start = { line = 0, character = 0 }, ['end'] = { line = 100, character = 0 } },
    }
    for _, response in pairs(vim.lsp.buf_request_sync(bufnr, 'textDocument/inlayHint', params, 10000) or {}) do
      for _, h in ipairs(response.result or {}) do
        table.insert(out, string.format('%d %s', h.position.line, h.label))
      end
    end
    return out
  end
  local ns = vim.api.nvim_create_namespace('hipop-plan')
  for _, mark in ipairs(vim.api.nvim_buf_get_extmarks(bufnr, ns, 0, -1, { details = true })) do
    table.insert(out, string.format('%d %s', mark[2], mark[4].virt_text[1][1]))
  end
  return out
end

local function run()
  local path = os.getenv('HIPOP_PROBLEM')
  vim.cmd('edit ' .. vim.fn.fnameescape(path))
  local bufnr = vim.api.nvim_get_current_buf()
  vim.wait(10000, function() return next(vim.lsp.buf_get_clients(bufnr)) ~= nil end, 20)
  -- Initialized once the server has answered a request.
  vim.lsp.buf_request_sync(bufnr, 'textDocument/documentSymbol', { textDocument = { uri = vim.uri_from_bufnr(bufnr) } }, 10000)
  vim.cmd('write')
  if not vim.wait(30000, function() return planned end, 20) then
    say('TIMEOUT waiting for the plan')
    return
  end
  if not vim.wait(10000, function() return #hints(bufnr) > 0 end, 50) then
    say('TIMEOUT waiting for the hints')
  end
  for _, h in ipairs(hints(bufnr)) do
    say('hint %s', masked(h))
  end

  -- The plan in a split.
  vim.cmd('HipopPlan')
  local plan = vim.api.nvim_get_current_buf()
  local text = table.concat(vim.api.nvim_buf_get_lines(plan, 0, -1, false), '\n')
  say('plan buffer: %s, modifiable %s, has the move %s', vim.bo[plan].filetype, tostring(vim.bo[plan].modifiable),
    tostring(text:find('(move r1 a b)', 1, true) ~= nil))
  vim.cmd('close')

  -- Completion in the goal offers the domain's predicates.
  local where = { textDocument = { uri = vim.uri_from_bufnr(bufnr) }, position = { line = 5, character = 15 } }
  local offered = {}
  for _, response in pairs(vim.lsp.buf_request_sync(bufnr, 'textDocument/completion', where, 10000) or {}) do
    local items = response.result and (response.result.items or response.result) or {}
    for _, item in ipairs(items) do
      offered[item.label] = true
    end
  end
  say('completion in the goal: at %s, visible %s, observed %s', tostring(offered['at'] == true),
    tostring(offered['visible'] == true), tostring(offered['observed'] == true))

  -- Rename a predicate of the domain from the problem: both files change.
  local uri = vim.uri_from_bufnr(bufnr)
  local params = { textDocument = { uri = uri }, position = { line = 5, character = 18 }, newName = 'seen' }
  for _, response in pairs(vim.lsp.buf_request_sync(bufnr, 'textDocument/rename', params, 10000) or {}) do
    if response.result then
      vim.lsp.util.apply_workspace_edit(response.result, 'utf-16')
    end
  end
  for _, name in ipairs({ 'problem.pddl', 'domain.pddl' }) do
    local b = vim.fn.bufnr(vim.fn.fnamemodify(path, ':h') .. '/' .. name)
    local all = table.concat(vim.api.nvim_buf_get_lines(b, 0, -1, false), '\n')
    local _, seen = all:gsub('%(seen ', '')
    local _, observed = all:gsub('observed', '')
    say('renamed in %s: %d seen, %d observed', name, seen, observed)
  end

  -- Formatting through the server gives `hipop fmt`'s text, and again the same.
  vim.api.nvim_set_current_buf(bufnr)
  local function text_of(b) return table.concat(vim.api.nvim_buf_get_lines(b, 0, -1, false), '\n') .. '\n' end
  local expected = vim.fn.system({ vim.g.hipop_cmd[1], 'fmt', '-' }, text_of(bufnr))
  local function format()
    if vim.lsp.buf.format then
      vim.lsp.buf.format({ bufnr = bufnr, timeout_ms = 10000 })
    else
      vim.lsp.buf.formatting_sync(nil, 10000)
    end
  end
  local before = text_of(bufnr)
  format()
  local once = text_of(bufnr)
  format()
  say('format: changed %s, as hipop fmt %s, idempotent %s', tostring(once ~= before), tostring(once == expected),
    tostring(text_of(bufnr) == once))

  -- The surveillance sample: its plan's summary, and a hint per goal.
  planned = nil
  vim.cmd('edit ' .. vim.fn.fnameescape(os.getenv('HIPOP_SURVEILLANCE')))
  local sample = vim.api.nvim_get_current_buf()
  vim.wait(10000, function() return next(vim.lsp.buf_get_clients(sample)) ~= nil end, 20)
  vim.lsp.buf_request_sync(sample, 'textDocument/documentSymbol', { textDocument = { uri = vim.uri_from_bufnr(sample) } }, 10000)
  vim.cmd('write')
  if not vim.wait(60000, function() return planned end, 20) then
    say('TIMEOUT waiting for the plan of the surveillance sample')
  else
    vim.wait(10000, function() return #hints(sample) > 0 end, 50)
    local shown = hints(sample)
    local goals = 0
    for _, h in ipairs(shown) do
      local _, n = h:gsub('← ', '')
      goals = goals + n
    end
    table.sort(shown)
    say('surveillance: %s; %d goal hints', masked(shown[1] or 'none'), goals)
  end

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
