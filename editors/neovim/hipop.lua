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

local cmd = vim.g.hipop_cmd or { 'hipop', 'lsp' }
if type(cmd) == 'string' then
  cmd = { cmd, 'lsp' }
end
local markers = vim.g.hipop_root_markers or { '.git', '.hg' }

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

local function attach(bufnr)
  local path = vim.api.nvim_buf_get_name(bufnr)
  if path == '' or vim.bo[bufnr].buftype ~= '' then
    return
  end
  local root = root_of(path)
  local config = { name = 'hipop', cmd = cmd, root_dir = root }
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
