-- Driven by lsp/tests/neovim.rs: opens $HIPOP_FILE, attaches `$HIPOP_BIN lsp`,
-- and writes what Neovim received (its diagnostics, then a hover) to
-- $HIPOP_OUT, one per line. Neovim 0.7 API only: vim.lsp.start_client,
-- vim.lsp.buf_attach_client, vim.diagnostic, vim.wait.
local lines = {}

local function run()
  local file = os.getenv('HIPOP_FILE')
  vim.cmd('edit ' .. vim.fn.fnameescape(file))
  local bufnr = vim.api.nvim_get_current_buf()
  local client_id = vim.lsp.start_client({
    name = 'hipop',
    cmd = { os.getenv('HIPOP_BIN'), 'lsp' },
    root_dir = vim.fn.fnamemodify(file, ':p:h'),
  })
  assert(client_id, 'vim.lsp.start_client failed')
  vim.lsp.buf_attach_client(bufnr, client_id)

  local got = vim.wait(20000, function() return #vim.diagnostic.get(bufnr) > 0 end, 50)
  if not got then
    table.insert(lines, 'TIMEOUT waiting for diagnostics')
  end
  local diags = vim.diagnostic.get(bufnr)
  table.sort(diags, function(a, b) return a.lnum < b.lnum or (a.lnum == b.lnum and a.col < b.col) end)
  for _, d in ipairs(diags) do
    -- Columns are byte columns: Neovim converted them from the UTF-16 the server sent.
    table.insert(lines, string.format('diagnostic %d:%d-%d:%d %s %s',
      d.lnum, d.col, d.end_lnum, d.end_col, tostring(d.code), d.message))
  end

  local params = {
    textDocument = { uri = vim.uri_from_bufnr(bufnr) },
    position = { line = tonumber(os.getenv('HIPOP_HOVER_LINE')), character = tonumber(os.getenv('HIPOP_HOVER_CHAR')) },
  }
  local responses = vim.lsp.buf_request_sync(bufnr, 'textDocument/hover', params, 10000) or {}
  for _, response in pairs(responses) do
    if response.result then
      for line in vim.gsplit(response.result.contents.value or '', '\n', true) do
        table.insert(lines, 'hover ' .. line)
      end
    else
      table.insert(lines, 'hover error ' .. vim.inspect(response.err))
    end
  end

  vim.lsp.stop_client(client_id)
  vim.wait(5000, function() return vim.lsp.client_is_stopped(client_id) end, 50)
end

local ok, err = pcall(run)
if not ok then
  table.insert(lines, 'ERROR ' .. tostring(err))
end
local out = assert(io.open(os.getenv('HIPOP_OUT'), 'w'))
out:write(table.concat(lines, '\n') .. '\n')
out:close()
vim.cmd('qa!')
