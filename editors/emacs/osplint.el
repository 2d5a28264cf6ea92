;;; osplint.el --- Okuma OSP part programs with the osplint language server  -*- lexical-binding: t; -*-

;; Eglot (built into Emacs 29; the elpa-eglot package on Emacs 28) talks to
;; `osplint lsp'. Load this file from your init file, e.g.
;; (load "/path/to/osplint/editors/emacs/osplint.el").

;;; Code:

(defvar osp-mode-syntax-table
  (let ((table (make-syntax-table)))
    ;; ( ... ) is a comment; none passes the end of its line.
    (modify-syntax-entry ?\( "<" table)
    (modify-syntax-entry ?\) ">" table)
    (modify-syntax-entry ?\n ">" table)
    (modify-syntax-entry ?\[ "(]" table)
    (modify-syntax-entry ?\] ")[" table)
    (modify-syntax-entry ?' "\"" table)
    table)
  "Syntax table of `osp-mode'.")

(defconst osp-font-lock-keywords
  `(;; A program name starting its line, a sequence name starting its block.
    ("^\\s-*\\(O[[:alnum:]]+\\)" 1 font-lock-function-name-face)
    ("^\\s-*/?\\s-*\\(N\\(?:CYL\\|OEX\\|MSG\\)\\)\\_>" 1 font-lock-keyword-face)
    ("^\\s-*/?\\s-*\\(N[[:alnum:]]+\\)" 1 font-lock-constant-face)
    ;; CALL / MODIN and their target, GOTO and IF and theirs.
    ("\\_<\\(CALL\\|MODIN\\)\\s-*\\(O[[:alnum:]]+\\)"
     (1 font-lock-keyword-face) (2 font-lock-function-name-face))
    ("\\_<\\(GOTO\\)\\s-*\\(N[[:alnum:]]+\\)" (1 font-lock-keyword-face) (2 font-lock-constant-face))
    ("\\]\\s-*\\(N[[:alnum:]]+\\)" 1 font-lock-constant-face)
    (,(regexp-opt '("IF" "WHILE" "DO" "END" "MODOUT" "RTS" "THEN" "NCYL" "NOEX") 'symbols)
     . font-lock-keyword-face)
    (,(regexp-opt '("EQ" "NE" "GT" "GE" "LT" "LE" "AND" "OR" "EOR" "NOT" "EMPTY") 'symbols)
     . font-lock-builtin-face)
    ;; G and M codes, variables, arguments.
    ("\\_<[GM][0-9]+\\_>" . font-lock-builtin-face)
    ("\\_<\\(?:VC[0-9]*\\|V[0-9]+\\|V[A-Z]\\{2,5\\}[0-9]?\\)\\_>" . font-lock-variable-name-face)
    ("\\_<\\([A-Z][[:alnum:]]+\\)\\s-*=" 1 font-lock-variable-name-face))
  "Highlighting of `osp-mode' (any case).")

(define-derived-mode osp-mode prog-mode "OSP"
  "Major mode for Okuma OSP part programs."
  :syntax-table osp-mode-syntax-table
  (setq-local comment-start "(")
  (setq-local comment-end ")")
  (setq-local comment-start-skip "(\\s-*")
  (setq-local font-lock-defaults '(osp-font-lock-keywords nil t)))

(defconst osplint-file-regexp
  "\\.\\([Mm][Ii][Nn]\\|[Ss][Ss][Bb]\\|[Ss][Uu][Bb]\\|[Ss][Dd][Ff]\\|[Ll][Ii][Bb]\\|[Mm][Ss][Bb]\\|[Nn][Cc]\\)\\'"
  "OSP program files: .MIN .SSB .SUB .SDF .LIB .MSB .NC, in any case.")

(add-to-list 'auto-mode-alist (cons osplint-file-regexp 'osp-mode))

(with-eval-after-load 'eglot
  (add-to-list 'eglot-server-programs '(osp-mode . ("osplint" "lsp"))))

(add-hook 'osp-mode-hook #'eglot-ensure)

(provide 'osplint)
;;; osplint.el ends here
