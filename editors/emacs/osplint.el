;;; osplint.el --- Okuma OSP part programs with the osplint language server  -*- lexical-binding: t; -*-

;; Eglot (built into Emacs 29) talks to `osplint lsp'. Load this file from
;; your init file, e.g. (load "/path/to/osplint/editors/emacs/osplint.el").

;;; Code:

(define-derived-mode osp-mode prog-mode "OSP"
  "Major mode for Okuma OSP part programs."
  (setq-local comment-start "(")
  (setq-local comment-end ")")
  (setq-local comment-start-skip "(\\s-*"))

(defconst osplint-file-regexp
  "\\.\\([Mm][Ii][Nn]\\|[Ss][Ss][Bb]\\|[Ss][Uu][Bb]\\|[Ss][Dd][Ff]\\|[Ll][Ii][Bb]\\|[Mm][Ss][Bb]\\|[Nn][Cc]\\)\\'"
  "OSP program files: .MIN .SSB .SUB .SDF .LIB .MSB .NC, in any case.")

(add-to-list 'auto-mode-alist (cons osplint-file-regexp 'osp-mode))

(with-eval-after-load 'eglot
  (add-to-list 'eglot-server-programs '(osp-mode . ("osplint" "lsp"))))

(add-hook 'osp-mode-hook #'eglot-ensure)

(provide 'osplint)
;;; osplint.el ends here
