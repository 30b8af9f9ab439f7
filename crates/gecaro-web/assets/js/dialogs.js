// The page's one modal dialog: a title, a body, OK and Cancel; an error
// line that keeps the dialog open.
import { $ } from './dom.js';

export function openDialog({ title, body, ok = 'OK', onOk }) {
  const dialog = $('dialog');
  $('dialog-title').textContent = title;
  $('dialog-body').replaceChildren(body);
  $('dialog-error').textContent = '';
  const okButton = $('dialog-ok');
  okButton.textContent = ok;
  okButton.hidden = !onOk;
  // A dialog with nothing to confirm is closed, not cancelled.
  $('dialog-cancel').textContent = onOk ? 'Cancel' : 'Close';
  $('dialog-form').onsubmit = async (event) => {
    event.preventDefault();
    if (!onOk) return;
    okButton.disabled = true;
    try {
      await onOk();
      dialog.close();
    } catch (error) {
      $('dialog-error').textContent = error.message;
    } finally {
      okButton.disabled = false;
    }
  };
  dialog.showModal();
  const first = body.querySelector && body.querySelector('input');
  if (first) first.focus();
}

export function dialogError(text) {
  $('dialog-error').textContent = text;
}
