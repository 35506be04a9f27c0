"""The stamp language server (``stampc lsp``, docs/lsp.md): ``symbols`` classifies the
AST's names, ``workspace`` resolves them over a file's scope and runs the checks,
``features`` renders hover, completion and formatting, ``server`` speaks LSP (pygls)."""
