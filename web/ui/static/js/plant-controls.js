// The plant sliders of the Emulator pages (MovingCap and FAULHABER): supply voltage and ambient
// temperature, each one fault injection of its kind (drive.supply, drive.ambient) that a move of
// the slider replaces, and their reset buttons. `prefix` names the page's elements (`emu`, `fh`):
// <prefix>-supply, -supply-value, -supply-reset, -ambient, -ambient-value, -ambient-reset.
// `reload()` refreshes the page's list of injections; the page calls sync(injections) after each.
import { api, describe } from './api.js';
import { $, action, showResult } from './ui.js';

export function plantControls({ prefix, supply, result, reload }) {
  $(`${prefix}-supply`).max = String(Math.ceil(supply.overV + 10));
  const sliders = {
    'drive.supply': { input: $(`${prefix}-supply`), out: $(`${prefix}-supply-value`), field: 'volts', unit: 'V', nominal: supply.nominalV },
    'drive.ambient': { input: $(`${prefix}-ambient`), out: $(`${prefix}-ambient-value`), field: 'celsius', unit: '°C', nominal: 25 },
  };
  let latest = [];
  // Replaces the active injections of `kind` by one with `fields` (or none). One replacement at a
  // time, each from the server's current list, so that quick slider moves leave exactly one.
  let replacing = Promise.resolve();
  function replaceInjection(kind, fields) {
    const run = async () => {
      const old = (await api.get('/api/v1/faults')).faults.filter((f) => f.kind === kind);
      if (fields) await api.post('/api/v1/faults', { kind, ...fields });
      for (const f of old) await api.del(`/api/v1/faults/${f.id}`);
      await reload();
    };
    const done = replacing.then(run, run);
    replacing = done.catch(() => {});
    return done;
  }
  let sliderBusy = false;
  function sync(injections = latest) {
    latest = injections;
    if (sliderBusy) return;
    for (const [kind, s] of Object.entries(sliders)) {
      const f = injections.find((x) => x.kind === kind);
      const v = f ? f[s.field] : s.nominal;
      if (document.activeElement !== s.input) s.input.value = String(v);
      s.out.value = `${v} ${s.unit}${f ? '' : ' (nominal)'}`;
    }
  }
  for (const [kind, s] of Object.entries(sliders)) {
    s.input.addEventListener('input', () => (s.out.value = `${s.input.value} ${s.unit}`));
    s.input.addEventListener('change', async () => {
      sliderBusy = true;
      try {
        await replaceInjection(kind, { [s.field]: Number(s.input.value) });
        showResult(result, true, `${kind} ${s.input.value} ${s.unit}`);
      } catch (e) {
        showResult(result, false, describe(e));
      } finally {
        sliderBusy = false;
        sync();
      }
    });
  }
  action($(`${prefix}-supply-reset`), async () => (await replaceInjection('drive.supply', null), `supply back to nominal (${supply.nominalV} V)`), result);
  action($(`${prefix}-ambient-reset`), async () => (await replaceInjection('drive.ambient', null), 'ambient back to 25 °C'), result);
  return { replaceInjection, sync };
}
