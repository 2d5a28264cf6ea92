-- End-to-end test of `osplint lsp` with Neovim's built-in client (0.7+, no
-- plugins), through the shipped setup (editors/neovim/osplint.lua).
--
-- Environment: OSPLINT_BIN (the osplint executable), OSPLINT_FILE (a copy of a
-- clean example that calls OZAGR), OSPLINT_REPO (the source tree).
-- Exits 0 when every step passed, 1 otherwise (cquit).
local bin = assert(os.getenv('OSPLINT_BIN'))
local file = assert(os.getenv('OSPLINT_FILE'))
local repo = assert(os.getenv('OSPLINT_REPO'))

local function out(msg)
  io.stdout:write(msg .. '\n')
  io.stdout:flush()
end

local failed = false
local function check(ok, what, detail)
  if ok then
    out('ok: ' .. what)
  else
    failed = true
    out('not ok: ' .. what .. (detail and (': ' .. detail) or ''))
  end
  return ok
end

local function finish()
  if failed then
    vim.cmd('cquit 1')
  else
    vim.cmd('qall!')
  end
end

local function abort(msg)
  check(false, msg)
  finish()
end

-- Every publishDiagnostics, as sent (the default handler still runs).
local published = {}
local default_publish = vim.lsp.handlers['textDocument/publishDiagnostics']
local handlers = {
  ['textDocument/publishDiagnostics'] = function(err, result, ctx, config)
    table.insert(published, result)
    return default_publish(err, result, ctx, config)
  end,
}

-- Tree-sitter highlighting: the script builds the parser from grammar/src and
-- puts it with grammar/queries/highlights.scm in OSPLINT_TS_RTP.
local ts_rtp = os.getenv('OSPLINT_TS_RTP')
if ts_rtp and ts_rtp ~= '' then
  vim.opt.rtp:prepend(ts_rtp)
else
  ts_rtp = nil
end

local osplint = dofile(repo .. '/editors/neovim/osplint.lua')
osplint.setup({ cmd = { bin, 'lsp' }, handlers = handlers, highlight = ts_rtp ~= nil })

vim.cmd('edit ' .. vim.fn.fnameescape(file))
local buf = vim.api.nvim_get_current_buf()
check(vim.bo[buf].filetype == 'osp', 'the setup marks the program as filetype osp', vim.bo[buf].filetype)

if ts_rtp then
  check(vim.treesitter.highlighter.active[buf] ~= nil, 'tree-sitter highlighting is on for the buffer')
  local query = vim.treesitter.query.get_query('osp', 'highlights')
  local parser = vim.treesitter.get_parser(buf, 'osp')
  local root = parser:parse()[1]:root()
  local seen = {}
  for id, node in query:iter_captures(root, buf, 0, -1) do
    local name = query.captures[id]
    local text = vim.treesitter.query.get_node_text(node, buf)
    if name == 'keyword' and text == 'CALL' then seen.call = true end
    if name == 'comment' then seen.comment = true end
    if name == 'number' then seen.number = true end
  end
  check(seen.call and seen.comment and seen.number and not root:has_error(),
    'grammar/queries/highlights.scm captures CALL, comments and numbers', vim.inspect(seen))
end

local function client()
  local clients = vim.lsp.buf_get_clients(buf)
  for _, c in pairs(clients) do
    if c.name == 'osplint' then
      return c
    end
  end
end

if not vim.wait(10000, function() return client() ~= nil and client().initialized end, 20) then
  abort('the server starts and initializes')
end
local c = client()
check(true, 'the server starts and initializes')
check(c.server_capabilities == nil or c.server_capabilities.hoverProvider == true or
  (c.resolved_capabilities and c.resolved_capabilities.hover), 'hover is advertised')

local function codes(result)
  local list = {}
  for _, d in ipairs(result.diagnostics) do
    table.insert(list, d.code or '?')
  end
  return table.concat(list, ',')
end

-- 1. Diagnostics of the clean example: an empty list for this document.
local uri = vim.uri_from_bufnr(buf)
if not vim.wait(10000, function() return #published > 0 end, 20) then
  abort('diagnostics are published after open')
end
check(published[#published].uri == uri and #published[#published].diagnostics == 0,
  'the clean example has no findings', codes(published[#published]))

-- 2. Hover on the macro name of the first CALL OZAGR line.
local lines = vim.api.nvim_buf_get_lines(buf, 0, -1, false)
local call_line
for i, l in ipairs(lines) do
  if l:find('^CALL OZAGR') then
    call_line = i - 1
    break
  end
end
if not call_line then
  abort('the example has a CALL OZAGR line')
end
local resp = vim.lsp.buf_request_sync(buf, 'textDocument/hover',
  { textDocument = { uri = uri }, position = { line = call_line, character = 7 } }, 5000)
local hover
for _, r in pairs(resp or {}) do
  hover = r.result
end
local text = hover and hover.contents and hover.contents.value or ''
check(text:find('OZAGR', 1, true) and text:find('Back counterboring with the BIG back%-counterbore bar'),
  'hover on OZAGR shows the macro card', text:sub(1, 200))
check(hover and hover.contents.kind == 'markdown', 'the card is Markdown')

-- 2b. The same through K, the mapping the setup makes: a floating window with the card.
local kmap = vim.fn.maparg('K', 'n', false, true)
check(type(kmap) == 'table' and kmap.buffer == 1, 'the setup maps K in the buffer', vim.inspect(kmap))
vim.api.nvim_win_set_cursor(0, { call_line + 1, 7 })
vim.cmd('normal K')
local float_text
vim.wait(5000, function()
  for _, w in ipairs(vim.api.nvim_list_wins()) do
    if vim.api.nvim_win_get_config(w).relative ~= '' then
      local b = vim.api.nvim_win_get_buf(w)
      float_text = table.concat(vim.api.nvim_buf_get_lines(b, 0, -1, false), '\n')
      return true
    end
  end
  return false
end, 20)
check(float_text and float_text:find('OZAGR', 1, true), 'K shows the macro card in a floating window',
  float_text and float_text:sub(1, 120))
for _, w in ipairs(vim.api.nvim_list_wins()) do
  if vim.api.nvim_win_get_config(w).relative ~= '' then
    vim.api.nvim_win_close(w, true)
  end
end

-- 3. Introduce a mistake: M52 on the CALL line, after a comment with
--    non-ASCII text (the client sends UTF-16 columns).
local before = #published
local old = lines[call_line + 1]
local comment = ' (裏ザグリ 🔧)'
vim.api.nvim_buf_set_text(buf, call_line, #old, call_line, #old, { comment .. ' M52' })
local found
if not vim.wait(10000, function()
  for i = before + 1, #published do
    for _, d in ipairs(published[i].diagnostics) do
      if d.code == 'OSP104' then
        found = d
      end
    end
  end
  return found ~= nil
end, 20) then
  abort('the edit brings a new OSP104 diagnostic')
end
check(true, 'the edit brings a new OSP104 diagnostic: ' .. found.message:sub(1, 60))
local new_line = vim.api.nvim_buf_get_lines(buf, call_line, call_line + 1, false)[1]
local m52_byte = new_line:find('M52', 1, true) - 1
local _, m52_utf16 = vim.str_utfindex(new_line, m52_byte)
check(found.range.start.line == call_line and found.range.start.character == m52_utf16,
  'the diagnostic is on M52, columns in UTF-16 past the emoji',
  vim.inspect(found.range.start) .. ' expected ' .. m52_utf16)
check(found.codeDescription and found.codeDescription.href:find('OSP104.md', 1, true), 'the rule doc link is set')

-- 4. The quick fix from the diagnostic, applied by the client.
resp = vim.lsp.buf_request_sync(buf, 'textDocument/codeAction', {
  textDocument = { uri = uri },
  range = found.range,
  context = { diagnostics = { found } },
}, 5000)
local fix, suppress
for _, r in pairs(resp or {}) do
  for _, a in ipairs(r.result or {}) do
    if a.title == 'Replace M52 by PM=52' then fix = a end
    if a.title == 'Suppress OSP104 on this block' then suppress = a end
  end
end
check(suppress ~= nil, 'a suppression is offered')
if not check(fix ~= nil, 'the quick fix is offered') then
  finish()
end
before = #published
vim.lsp.util.apply_workspace_edit(fix.edit, 'utf-16')
new_line = vim.api.nvim_buf_get_lines(buf, call_line, call_line + 1, false)[1]
check(new_line:sub(-#(comment .. ' PM=52')) == comment .. ' PM=52', 'the fix rewrote M52 as PM=52', new_line)
local clean = vim.wait(10000, function()
  local last = published[#published]
  return #published > before and last.uri == uri and #last.diagnostics == 0
end, 20)
check(clean, 'after the fix the diagnostics are empty again', codes(published[#published]))

-- 5. Rename a sequence name (N2 -> N20) through the client, with prepareRename.
local n2_line
for i, l in ipairs(vim.api.nvim_buf_get_lines(buf, 0, -1, false)) do
  if l:find('^N2 ') then
    n2_line = i
  end
end
if check(n2_line ~= nil, 'the example has an N2 block') then
  check(vim.fn.maparg('<leader>rn', 'n', false, true).buffer == 1, 'the setup maps <leader>rn in the buffer')
  vim.api.nvim_win_set_cursor(0, { n2_line, 0 })
  vim.lsp.buf.rename('N20')
  local renamed = vim.wait(5000, function()
    return vim.api.nvim_buf_get_lines(buf, n2_line - 1, n2_line, false)[1]:find('^N20 ') ~= nil
  end, 20)
  check(renamed, 'rename rewrites the sequence name',
    vim.api.nvim_buf_get_lines(buf, n2_line - 1, n2_line, false)[1])
end

-- 6. Shutdown and exit.
local exited
c.config.on_exit = function(code)
  exited = code
end
vim.lsp.stop_client(c.id)
vim.wait(5000, function() return vim.lsp.client_is_stopped(c.id) end, 20)
check(vim.lsp.client_is_stopped(c.id), 'the server shuts down on request')
finish()
