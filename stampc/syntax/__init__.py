"""stampc.syntax: stamp source text → AST (``parser.parse_source``), the AST
(``ast``), and the canonical printer (``fmt.format_program``). Lark stays inside."""
