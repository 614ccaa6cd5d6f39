-- hipop for Neovim 0.7 or later: file types for domains, problems and plans,
-- and the hipop language server attached to them. No plugin needed.
--
-- Load it from your init.lua (or copy it to ~/.config/nvim/plugin/):
--
--   dofile('/path/to/hipop/editors/neovim/hipop.lua')
--
-- Settings, to set before loading it:
--   vim.g.hipop_cmd   the server command, a list (default { 'hipop', 'lsp' });
--                     a string is the path of the binary.
--   vim.g.hipop_root_markers  files or folders whose folder is the workspace
--                     (default { '.git', '.hg' }); without one, the file's folder.
--   vim.g.hipop_plan_on_save  plan a problem when it is saved (default true)
--   vim.g.hipop_plan_time_limit  the planner's budget in seconds (default 5)
--
-- Commands: :HipopPlan (the last plan of the problem, in a split),
-- :HipopPlanDiff (what the last repair changed, side by side), :HipopWritePlan
-- (writes NAME.plan beside the problem).

local cmd = vim.g.hipop_cmd or { 'hipop', 'lsp' }
if type(cmd) == 'string' then
  cmd = { cmd, 'lsp' }
end
local markers = vim.g.hipop_root_markers or { '.git', '.hg' }
local init_options = {
  plan = {
    onSave = vim.g.hipop_plan_on_save ~= false and vim.g.hipop_plan_on_save ~= 0,
    timeLimit = vim.g.hipop_plan_time_limit or 5,
  },
}

-- The file names the server reads (docs/plan-formats.md): domains and
-- problems, plans, JSON plans.
local patterns = { '*.pddl', '*.hddl', '*.plan', '*.soln', '*.sol', '*.plan.json' }

local group = vim.api.nvim_create_augroup('hipop', { clear = true })

-- File types: `pddl` for domains and problems, `hipop-plan` for plans
-- (Neovim calls `*.sol` Solidity: remove '*.sol' from `patterns` and here if
-- you edit Solidity); JSON plans stay `json`. Comments are `;`.
vim.api.nvim_create_autocmd({ 'BufRead', 'BufNewFile' }, {
  group = group,
  pattern = { '*.pddl', '*.hddl' },
  callback = function() vim.bo.filetype = 'pddl' end,
})
vim.api.nvim_create_autocmd({ 'BufRead', 'BufNewFile' }, {
  group = group,
  pattern = { '*.plan', '*.soln', '*.sol' },
  callback = function() vim.bo.filetype = 'hipop-plan' end,
})
vim.api.nvim_create_autocmd('FileType', {
  group = group,
  pattern = { 'pddl', 'hipop-plan' },
  callback = function()
    vim.bo.commentstring = '; %s'
    vim.bo.comments = ':;'
  end,
})

-- The workspace of a file: the nearest folder above it with a marker, else its own.
local function root_of(path)
  local dir = vim.fn.fnamemodify(path, ':p:h')
  for _, marker in ipairs(markers) do
    local found = vim.fn.finddir(marker, dir .. ';')
    if found == '' then
      found = vim.fn.findfile(marker, dir .. ';')
    end
    if found ~= '' then
      return vim.fn.fnamemodify(found, ':p:h:h')
    end
  end
  return dir
end

-- One server per workspace, shared by its buffers (Neovim 0.7 has no
-- vim.lsp.start, which does this from 0.8 on).
local clients = {}

-- The plan on save, inline: Neovim 0.10 and later show the server's inlay
-- hints; older versions get them as virtual text at the end of their lines.
local hints_ns = vim.api.nvim_create_namespace('hipop-plan')
local native_hints = vim.lsp.inlay_hint ~= nil

local function client_of(bufnr)
  for _, client in pairs(vim.lsp.buf_get_clients(bufnr)) do
    if client.name == 'hipop' then
      return client
    end
  end
end

-- Asks the hints of a buffer and shows them as virtual text (Neovim < 0.10).
local function show_hints(bufnr)
  local client = client_of(bufnr)
  if native_hints or not client or not vim.api.nvim_buf_is_loaded(bufnr) then
    return
  end
  local params = {
    textDocument = { uri = vim.uri_from_bufnr(bufnr) },
    range = { start = { line = 0, character = 0 }, ['end'] = { line = vim.api.nvim_buf_line_count(bufnr), character = 0 } },
  }
  client.request('textDocument/inlayHint', params, function(err, hints)
    if err or not vim.api.nvim_buf_is_loaded(bufnr) then
      return
    end
    vim.api.nvim_buf_clear_namespace(bufnr, hints_ns, 0, -1)
    local per_line = {}
    for _, hint in ipairs(hints or {}) do
      local label = type(hint.label) == 'string' and hint.label or ''
      local line = hint.position.line
      per_line[line] = per_line[line] and (per_line[line] .. '  ' .. label) or label
    end
    for line, text in pairs(per_line) do
      if line < vim.api.nvim_buf_line_count(bufnr) then
        vim.api.nvim_buf_set_extmark(bufnr, hints_ns, line, 0, { virt_text = { { text, 'Comment' } }, virt_text_pos = 'eol' })
      end
    end
  end, bufnr)
end

-- The server says a run ended: refresh the hints of the problem's buffer.
local function on_planned(_, result)
  if not result or not result.uri then
    return
  end
  local bufnr = vim.uri_to_bufnr(result.uri)
  show_hints(bufnr)
  -- For a user's autocmd (`data` from Neovim 0.8 on).
  if not pcall(vim.api.nvim_exec_autocmds, 'User', { pattern = 'HipopPlanned', data = result, modeline = false }) then
    vim.api.nvim_exec_autocmds('User', { pattern = 'HipopPlanned', modeline = false })
  end
end

local function on_attach(client, bufnr)
  if native_hints and vim.bo[bufnr].filetype == 'pddl' then
    pcall(vim.lsp.inlay_hint.enable, true, { bufnr = bufnr })
  elseif not native_hints then
    vim.api.nvim_create_autocmd({ 'TextChanged', 'InsertLeave' }, {
      group = group,
      buffer = bufnr,
      callback = function() show_hints(bufnr) end,
    })
  end
end

local function attach(bufnr)
  local path = vim.api.nvim_buf_get_name(bufnr)
  if path == '' or vim.bo[bufnr].buftype ~= '' then
    return
  end
  local root = root_of(path)
  local config = {
    name = 'hipop',
    cmd = cmd,
    root_dir = root,
    init_options = init_options,
    on_attach = on_attach,
    handlers = { ['hipop/planned'] = on_planned },
  }
  if vim.lsp.start then
    vim.lsp.start(config, { bufnr = bufnr })
    return
  end
  local id = clients[root]
  if not id or vim.lsp.client_is_stopped(id) then
    id = vim.lsp.start_client(config)
    if not id then
      vim.notify('hipop: cannot start ' .. table.concat(cmd, ' '), vim.log.levels.ERROR)
      return
    end
    clients[root] = id
  end
  vim.lsp.buf_attach_client(bufnr, id)
end

vim.api.nvim_create_autocmd({ 'BufReadPost', 'BufNewFile' }, {
  group = group,
  pattern = patterns,
  callback = function(args) attach(args.buf) end,
})

-- A scratch buffer showing `text`, in a split (`split`: 'new' or 'vnew').
local function scratch(name, text, filetype, split)
  vim.cmd(split or 'new')
  local bufnr = vim.api.nvim_get_current_buf()
  vim.bo[bufnr].buftype = 'nofile'
  vim.bo[bufnr].bufhidden = 'wipe'
  vim.bo[bufnr].swapfile = false
  pcall(vim.api.nvim_buf_set_name, bufnr, name)
  vim.api.nvim_buf_set_lines(bufnr, 0, -1, false, vim.split(text, '\n', true))
  vim.bo[bufnr].filetype = filetype
  vim.bo[bufnr].modifiable = false
  return bufnr
end

-- Sends a request about the current buffer's problem (`params`, by default
-- its URI); calls `on_result` with its result, or says why there is none.
local function ask(method, on_result, params)
  local bufnr = vim.api.nvim_get_current_buf()
  local client = client_of(bufnr)
  if not client then
    vim.notify('hipop: no hipop server for this buffer', vim.log.levels.WARN)
    return
  end
  params = params or { uri = vim.uri_from_bufnr(bufnr) }
  local result, err = client.request_sync(method, params, 10000, bufnr)
  if err or not result or result.err then
    vim.notify('hipop: ' .. method .. ' failed: ' .. tostring(err or (result and result.err and result.err.message)), vim.log.levels.ERROR)
    return
  end
  on_result(result.result, bufnr)
end

vim.api.nvim_create_user_command('HipopPlan', function()
  ask('hipop/plan', function(plan)
    if not plan then
      vim.notify('hipop: no plan yet: save the problem to plan it', vim.log.levels.INFO)
    elseif not plan.text then
      vim.notify('hipop: ' .. plan.summary, vim.log.levels.INFO)
    else
      scratch('hipop://' .. plan.problem .. '.plan', plan.text, 'hipop-plan')
    end
  end)
end, { desc = 'hipop: the last plan of this problem' })

vim.api.nvim_create_user_command('HipopPlanDiff', function()
  ask('hipop/planDiff', function(diff)
    if not diff then
      vim.notify('hipop: the last run was not a repair: change the problem and save it again', vim.log.levels.INFO)
      return
    end
    scratch('hipop://before.plan', diff.old, 'hipop-plan')
    vim.cmd('diffthis')
    scratch('hipop://after.plan', diff.new, 'hipop-plan', 'vnew')
    vim.cmd('diffthis')
    vim.notify(string.format('hipop: instability %d, distance %d', diff.instability, diff.distance), vim.log.levels.INFO)
  end)
end, { desc = 'hipop: what the last repair of this problem changed' })

vim.api.nvim_create_user_command('HipopWritePlan', function()
  local params = { command = 'hipop.writePlan', arguments = { vim.uri_from_bufnr(0) } }
  ask('workspace/executeCommand', function(written)
    vim.notify('hipop: wrote ' .. written.path, vim.log.levels.INFO)
  end, params)
end, { desc = 'hipop: write the last plan of this problem beside it' })
