-- osplint for Neovim (0.7 or later), without plugins.
--
-- Put this file on 'runtimepath' as lua/osplint.lua (or dofile() it) and call
--
--     require('osplint').setup()                      -- `osplint` on $PATH
--     require('osplint').setup({ cmd = { '/path/to/osplint', 'lsp' } })
--
-- It marks Okuma OSP program files (.MIN .SSB .SUB .SDF .LIB .MSB .NC, any case) as
-- filetype `osp` and starts one `osplint lsp` per project root (the directory
-- of the nearest osplint.toml, else the file's directory). Diagnostics, hover
-- (K), go to definition (gd), references (gr), rename (<leader>rn), code
-- actions (<leader>ca) and completion (<C-x><C-o>) then work with Neovim's
-- built-in client. tests/scripts/lsp_neovim.sh runs this file against a real
-- Neovim.
local M = {}

-- Any case: `*.[Mm][Ii][Nn]` matches PART.MIN, part.min and Part.Min.
M.patterns = { '*.[Mm][Ii][Nn]', '*.[Ss][Ss][Bb]', '*.[Ss][Uu][Bb]', '*.[Ss][Dd][Ff]', '*.[Ll][Ii][Bb]',
  '*.[Mm][Ss][Bb]', '*.[Nn][Cc]' }

local clients = {} -- root directory -> client id (Neovim 0.7 path)

-- The directory of the nearest osplint.toml above `path`, else its directory.
function M.root_dir(path)
  local dir = vim.fn.fnamemodify(path, ':p:h')
  local found = vim.fn.findfile('osplint.toml', dir .. ';')
  if found ~= '' then
    return vim.fn.fnamemodify(found, ':p:h')
  end
  return dir
end

-- Starts (or reuses) the server for `bufnr` and attaches the buffer; returns the client id.
function M.attach(bufnr, opts)
  opts = opts or M.options or {}
  local path = vim.api.nvim_buf_get_name(bufnr)
  local root = M.root_dir(path ~= '' and path or vim.fn.getcwd() .. '/x')
  local config = {
    name = 'osplint',
    cmd = opts.cmd or { 'osplint', 'lsp' },
    root_dir = root,
    workspace_folders = { { uri = vim.uri_from_fname(root), name = root } },
    handlers = opts.handlers,
    on_attach = function(client, buf)
      vim.api.nvim_buf_set_option(buf, 'omnifunc', 'v:lua.vim.lsp.omnifunc')
      if opts.mappings ~= false then
        M.map(buf)
      end
      if opts.on_attach then
        opts.on_attach(client, buf)
      end
    end,
  }
  if vim.lsp.start then -- Neovim 0.8+
    return vim.lsp.start(config, { bufnr = bufnr })
  end
  local id = clients[root]
  if not id or not vim.lsp.get_client_by_id(id) then
    id = vim.lsp.start_client(config)
    clients[root] = id
  end
  vim.lsp.buf_attach_client(bufnr, id)
  return id
end

-- Buffer-local mappings (Neovim 0.7 sets none of them by itself): K hover,
-- gd go to definition, gr references, <leader>rn rename, <leader>ca code
-- actions. `mappings = false` in the options leaves the keys alone.
function M.map(buf)
  local function map(lhs, fn, desc)
    vim.keymap.set('n', lhs, fn, { buffer = buf, silent = true, desc = desc })
  end
  map('K', vim.lsp.buf.hover, 'osplint: hover')
  map('gd', vim.lsp.buf.definition, 'osplint: go to definition')
  map('gr', vim.lsp.buf.references, 'osplint: references')
  map('<leader>rn', vim.lsp.buf.rename, 'osplint: rename')
  map('<leader>ca', vim.lsp.buf.code_action, 'osplint: code actions')
end

-- Tree-sitter highlighting with osplint's own grammar (optional): build the
-- parser from grammar/src into <config>/parser/osp.so and copy
-- grammar/queries/highlights.scm to <config>/queries/osp/highlights.scm
-- (see editors/README.md). Does nothing when the parser is not installed.
function M.highlight(bufnr)
  if vim.treesitter.start then
    pcall(vim.treesitter.start, bufnr, 'osp')
  else
    local ok, parser = pcall(vim.treesitter.get_parser, bufnr, 'osp')
    if ok and parser then
      pcall(vim.treesitter.highlighter.new, parser)
    end
  end
end

function M.setup(opts)
  M.options = opts or {}
  local group = vim.api.nvim_create_augroup('osplint', { clear = true })
  vim.api.nvim_create_autocmd({ 'BufRead', 'BufNewFile' }, {
    group = group,
    pattern = M.patterns,
    callback = function(args)
      vim.api.nvim_buf_set_option(args.buf, 'filetype', 'osp')
    end,
  })
  vim.api.nvim_create_autocmd('FileType', {
    group = group,
    pattern = 'osp',
    callback = function(args)
      M.attach(args.buf, M.options)
      if M.options.highlight ~= false then
        M.highlight(args.buf)
      end
    end,
  })
end

return M
