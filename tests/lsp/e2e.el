;;; e2e.el --- End-to-end test of `osplint lsp' with Emacs and Eglot  -*- lexical-binding: t; -*-

;; Run by tests/scripts/lsp_emacs.sh in `emacs --batch' through the shipped
;; setup (editors/emacs/osplint.el). Environment: OSPLINT_BIN (the osplint
;; executable), OSPLINT_FILE (a copy of a clean example that calls OZAGR),
;; OSPLINT_REPO (the source tree). Exits 0 when every step passed.

(require 'package)
(package-initialize)
;; Debian's elpa-* packages (eglot and the newer project and xref it needs),
;; whether or not package.el activated them.
(dolist (dir (file-expand-wildcards "/usr/share/emacs/site-lisp/elpa/*"))
  (add-to-list 'load-path dir))
(require 'cl-lib)
(require 'eglot)
(require 'flymake)

(defvar e2e-failed nil)
(defun e2e-check (ok what &optional detail)
  (princ (format "%s: %s%s\n" (if ok "ok" "not ok") what
                 (if (and (not ok) detail) (format ": %s" detail) "")))
  (unless ok (setq e2e-failed t))
  ok)
(defun e2e-finish ()
  (kill-emacs (if e2e-failed 1 0)))
(defun e2e-wait (pred seconds)
  "Let timers and the server's output run until PRED holds, at most SECONDS."
  (let ((deadline (+ (float-time) seconds)))
    (while (and (not (funcall pred)) (< (float-time) deadline))
      (accept-process-output nil 0.05))
    (funcall pred)))

(let ((bin (getenv "OSPLINT_BIN"))
      (file (getenv "OSPLINT_FILE"))
      (repo (getenv "OSPLINT_REPO")))
  (load (expand-file-name "editors/emacs/osplint.el" repo) nil t)
  ;; The executable under test instead of `osplint' on PATH.
  (add-to-list 'eglot-server-programs `(osp-mode . (,bin "lsp")))
  (setq eglot-send-changes-idle-time 0.1)
  (find-file file)
  (e2e-check (eq major-mode 'osp-mode) "the setup puts the program in osp-mode" major-mode)
  (font-lock-ensure)
  (goto-char (point-min))
  (search-forward "CALL OZAGR")
  (e2e-check (and (eq (get-text-property (match-beginning 0) 'face) 'font-lock-keyword-face)
                  (eq (get-text-property (- (point) 2) 'face) 'font-lock-function-name-face))
             "CALL and its target are highlighted")
  ;; eglot-ensure (the mode hook) connects after the next command.
  (run-hooks 'post-command-hook)
  (unless (e2e-check (e2e-wait (lambda () (eglot-current-server)) 10) "Eglot connects to osplint lsp")
    (e2e-finish))
  (let ((server (eglot-current-server)))
    (e2e-check (eglot--server-capable :renameProvider) "rename is advertised")
    ;; 1. Hover on the macro name.
    (goto-char (point-min))
    (search-forward "CALL OZAG")
    (let* ((hover (jsonrpc-request server :textDocument/hover (eglot--TextDocumentPositionParams)))
           (text (plist-get (plist-get hover :contents) :value)))
      (e2e-check (and text (string-match-p "Back counterboring with the BIG back-counterbore bar" text))
                 "hover on OZAGR shows the macro card" text))
    ;; 2. A mistake: M52 on the CALL line; its diagnostic comes through Flymake.
    (end-of-line)
    (insert " M52")
    ;; Eglot sends changes from an idle timer, and batch Emacs is never idle.
    (eglot--signal-textDocument/didChange)
    (let ((diag nil))
      (e2e-wait (lambda ()
                  ;; Flymake starts its backends on its own only in a displayed buffer.
                  (when (and (bound-and-true-p flymake-mode) (not (flymake-running-backends)))
                    (flymake-start))
                  (setq diag (cl-find-if
                              (lambda (d)
                                (equal (plist-get (cdr (assoc 'eglot-lsp-diag (flymake-diagnostic-data d))) :code)
                                       "OSP104"))
                              (flymake-diagnostics (point-min) (point-max))))
                  diag)
                10)
      (e2e-check diag "the edit brings an OSP104 diagnostic")
      (when diag
        (e2e-check (equal (buffer-substring (flymake-diagnostic-beg diag) (flymake-diagnostic-end diag)) "M52")
                   "the diagnostic is on M52")
        ;; 3. The quick fix, as a code action applied by Eglot.
        (let* ((actions (eglot-code-actions (flymake-diagnostic-beg diag) (flymake-diagnostic-end diag) "quickfix"))
               (fix (cl-find-if (lambda (a) (equal (plist-get a :title) "Replace M52 by PM=52")) actions)))
          (when (e2e-check fix "the quick fix is offered" (mapcar (lambda (a) (plist-get a :title)) actions))
            (eglot--apply-workspace-edit (plist-get fix :edit))
            (e2e-check (string-suffix-p "PM=52" (buffer-substring (line-beginning-position) (line-end-position)))
                       "the fix rewrote M52 as PM=52"
                       (buffer-substring (line-beginning-position) (line-end-position)))))))
    ;; 4. Rename a sequence name.
    (goto-char (point-min))
    (re-search-forward "^N2 ")
    (beginning-of-line)
    (eglot-rename "N20")
    (e2e-check (looking-at "N20 (") "rename rewrites the sequence name"
               (buffer-substring (line-beginning-position) (line-end-position)))
    ;; 5. Shutdown.
    (set-buffer-modified-p nil)
    (eglot-shutdown server)
    (e2e-check (not (jsonrpc-running-p server)) "the server shuts down on request")))
(e2e-finish)
;;; e2e.el ends here
