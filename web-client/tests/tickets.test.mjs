// Unit tests of what the sign-in box makes of what a student pastes
// (src/api/tickets.ts's pastedTicket): a course's sign-in link, or its
// ticket alone, is redeemed; anything else is a token.  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { pastedTicket } = await importTs('api/tickets.ts');

test("a sign-in link's ticket is found wherever the link points", () => {
  const ticket = 'cgl_0123456789abcdef_' + 'ab'.repeat(32);
  assert.equal(pastedTicket(`http://lab.example:8080/#ticket=${ticket}`), ticket);
  assert.equal(pastedTicket(`  https://cgview.example/?x=1#ticket=${ticket}\n`), ticket, 'spaces and a newline around it');
  assert.equal(pastedTicket(`https://cgview.example/#ticket=${ticket}&view=abc`), ticket);
  assert.equal(pastedTicket(ticket), ticket, 'the ticket alone');
});

test('a token, or a notebook ticket, is not a sign-in link', () => {
  assert.equal(pastedTicket('cgv_0123456789abcdef_' + 'cd'.repeat(32)), null);
  assert.equal(pastedTicket('http://lab.example/#ticket=cgt_abc'), null);
  assert.equal(pastedTicket('http://lab.example/#view=cgl_abc'), null);
  assert.equal(pastedTicket(''), null);
});
