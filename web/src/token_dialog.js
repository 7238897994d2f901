// The Token button and dialog: the operator enters the token once; the page keeps it while it is open and
// reconnects as the operator.
import { isValidToken, storeToken } from './token.js';

const $ = (id) => document.getElementById(id);

export function setUpTokenDialog(connection, notices) {
  const dialog = $('token-dialog');
  $('token-button').addEventListener('click', () => {
    $('token-input').value = '';
    dialog.showModal();
  });
  dialog.addEventListener('close', () => {
    if (dialog.returnValue === 'use') {
      const token = $('token-input').value.trim();
      if (!isValidToken(token)) {
        notices.show('That is not a token: 16-128 letters, digits, - or _', 'error');
        return;
      }
      storeToken(token);
      connection.useToken(token);
    } else if (dialog.returnValue === 'forget') {
      storeToken(null);
      connection.useToken(null);
      notices.show('Token forgotten: watching as a viewer', 'info', 4);
    }
  });
}
