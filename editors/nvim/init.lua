-- raytrace's language server in Neovim, without nvim-lspconfig: `.rt`
-- files get the filetype `rt`, and each buffer of that type is attached to
-- `raytrace lsp` (one server per project root, found by `.git`).
-- Put this in your init.lua, or load it: `nvim -u editors/nvim/init.lua`.
-- RAYTRACE in the environment names the program (default: `raytrace` on PATH).

vim.filetype.add({ extension = { rt = 'rt' } })
if vim.fn.has('nvim-0.8') == 0 then
  -- Neovim 0.7 reads vim.filetype.add only when asked to.
  vim.g.do_filetype_lua = 1
end

local cmd = { os.getenv('RAYTRACE') or 'raytrace', 'lsp' }

local function root_of(buf)
  local file = vim.api.nvim_buf_get_name(buf)
  local git = vim.fs and vim.fs.find and vim.fs.find('.git', { path = file, upward = true })[1]
  return git and vim.fs.dirname(git) or vim.fn.fnamemodify(file, ':p:h')
end

vim.api.nvim_create_autocmd('FileType', {
  pattern = 'rt',
  callback = function(args)
    if vim.lsp.start then
      -- Neovim 0.8 and later.
      vim.lsp.start({ name = 'raytrace', cmd = cmd, root_dir = root_of(args.buf) })
    else
      -- Neovim 0.7: start a client and attach the buffer by hand.
      _G.raytrace_lsp = _G.raytrace_lsp
        or vim.lsp.start_client({ name = 'raytrace', cmd = cmd, root_dir = root_of(args.buf) })
      vim.lsp.buf_attach_client(args.buf, _G.raytrace_lsp)
    end
  end,
})

-- `//` comments for `gc` and friends.
vim.api.nvim_create_autocmd('FileType', {
  pattern = 'rt',
  callback = function() vim.bo.commentstring = '// %s' end,
})
