// One parameter's input, generated from its JSON Schema (API.md "Algorithms
// and jobs"): integer / number → a number input with min, max, step and the
// default; boolean → a checkbox; enum → a select; string → a text input; a
// selection (an array with x-cgview-selection: faces or vertices) → "use
// current selection (N faces)". The algorithm form and the playground's both
// build theirs with it, in the declared order (orderedParams).
import type { ParamSchema, ParamsSchema } from '../api/types.ts';
import { el } from './dom.ts';

/** The input of one parameter, how to read its value and how to put its default back. */
export interface Control {
  input: HTMLElement;
  read: () => unknown;
  reset: () => void;
}

function stepFor(schema: ParamSchema): string {
  if (schema.type === 'integer') return '1';
  if (typeof schema.multipleOf === 'number') return String(schema.multipleOf);
  const lo = typeof schema.minimum === 'number' ? schema.minimum : null;
  const hi = typeof schema.maximum === 'number' ? schema.maximum : null;
  if (lo !== null && hi !== null && hi > lo) {
    // About a hundredth of the range, a power of ten: 0.1..4 → 0.01.
    return String(10 ** Math.floor(Math.log10((hi - lo) / 100)));
  }
  return 'any';
}

/** The input of one parameter (also the playground's form), how to read its value and reset it. */
export function control(name: string, schema: ParamSchema, id: string, selection: (kind: string) => number[]): Control {
  const kind = schema['x-cgview-selection'];
  if (typeof kind === 'string') {
    const box = el('input', { id, name, type: 'checkbox', 'data-param': name, 'data-selection': kind });
    box.checked = true;
    const text = el('span', { class: 'selection-use', 'data-selection-kind': kind }, `use current selection (${selection(kind).length} ${kind})`);
    const label = el('label', { class: 'check' }, box, ' ', text);
    return { input: label, read: () => (box.checked ? selection(kind) : undefined), reset: () => void (box.checked = true) };
  }
  if (Array.isArray(schema.enum)) {
    const values = schema.enum;
    const select = el('select', { id, name, 'data-param': name });
    const initial = Math.max(
      0,
      values.findIndex((v) => v === schema.default),
    );
    values.forEach((v, i) => select.append(el('option', { value: String(i) }, String(v))));
    select.value = String(initial);
    return { input: select, read: () => values[Number(select.value)], reset: () => void (select.value = String(initial)) };
  }
  switch (schema.type) {
    case 'boolean': {
      const input = el('input', { id, name, type: 'checkbox', 'data-param': name });
      const reset = () => void (input.checked = schema.default === true);
      reset();
      return { input, read: () => input.checked, reset };
    }
    case 'integer':
    case 'number': {
      const input = el('input', { id, name, type: 'number', 'data-param': name, step: stepFor(schema) });
      if (typeof schema.minimum === 'number') input.min = String(schema.minimum);
      if (typeof schema.maximum === 'number') input.max = String(schema.maximum);
      const reset = () => void (input.value = typeof schema.default === 'number' ? String(schema.default) : '');
      reset();
      return {
        input,
        read: () => {
          const text = input.value.trim();
          if (text === '') return undefined;
          // What the user typed goes to the server as typed: it checks the rules.
          return Number(text);
        },
        reset,
      };
    }
    default: {
      const input = el('input', { id, name, type: 'text', 'data-param': name });
      const reset = () => void (input.value = typeof schema.default === 'string' ? schema.default : '');
      reset();
      return { input, read: () => input.value, reset };
    }
  }
}

/**
 * The names of the parameters in the algorithm's declared order: JSON keeps
 * object keys sorted, so the order comes in x-cgview-order; a parameter it
 * leaves out follows in the keys' order.
 */
export function orderedParams(params: ParamsSchema | undefined): string[] {
  const properties = params?.properties ?? {};
  const declared = Array.isArray(params?.['x-cgview-order']) ? params['x-cgview-order'] : [];
  const known = declared.filter((n): n is string => typeof n === 'string' && Object.hasOwn(properties, n));
  return [...new Set([...known, ...Object.keys(properties)])];
}
