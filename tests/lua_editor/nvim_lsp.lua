-- Neovim's own LSP client (vim.lsp.start_client, Neovim 0.7) on `luamotion lsp`: opens
-- LSP_FILE, waits for the diagnostics, asks for completion, hover and signature help,
-- and writes what it received into LSP_OUT, one fact per line. tests/lsp.rs reads it.
local out = assert(io.open(os.getenv("LSP_OUT"), "w"))
local function say(...) out:write(string.format(...), "\n") out:flush() end
vim.cmd("edit " .. vim.fn.fnameescape(os.getenv("LSP_FILE")))
local buf = vim.api.nvim_get_current_buf()
local id = vim.lsp.start_client({
  name = "luamotion",
  cmd = { os.getenv("LUAMOTION_BIN"), "lsp" },
  root_dir = vim.fn.fnamemodify(os.getenv("LSP_FILE"), ":h"),
})
vim.lsp.buf_attach_client(buf, id)
local got = vim.wait(20000, function() return #vim.diagnostic.get(buf) > 0 end, 20)
say("diagnostics %s", tostring(got))
for _, d in ipairs(vim.diagnostic.get(buf)) do
  local code = d.code or (d.user_data and d.user_data.lsp and d.user_data.lsp.code) or ""
  say("diagnostic %d:%d %s %s", d.lnum + 1, d.col + 1, code, (d.message:gsub("\n", " | ")))
end
local client = vim.lsp.get_client_by_id(id)
local at = function(line, character)
  return { textDocument = { uri = vim.uri_from_bufnr(buf) }, position = { line = line, character = character } }
end
local completion = client.request_sync("textDocument/completion", at(1, 4), 10000, buf)
local items = completion and completion.result or {}
items = items.items or items
say("completion items %d", #items)
for _, item in ipairs(items) do
  if item.label == "MoveAbs" or item.label == "BM_LOOKAHEAD" then
    say("completion %s %s", item.label, item.detail or "")
  end
end
local hover = client.request_sync("textDocument/hover", at(1, 2), 10000, buf)
local value = hover and hover.result and hover.result.contents and hover.result.contents.value or ""
say("hover %s", (value:gsub("\n", " | ")))
local signature = client.request_sync("textDocument/signatureHelp", at(1, 11), 10000, buf)
local help = signature and signature.result and signature.result.signatures and signature.result.signatures[1]
say("signature %s active %s", help and help.label or "none", tostring(signature and signature.result and signature.result.activeParameter))
out:close()
vim.cmd("qa!")
