#!/usr/bin/python3
"""lathectl_vibsensor (B's measuring chain on a real accelerometer) on a recorded chatter signal,
with no hardware: the twin-turret example's vibration (b_twin_feed_division at 1 mm depth, so
that it chatters within 5 s), simulated by rig B at 48 kHz and converted to acceleration
(tests/hal/vibsensor_record.cpp), played

  - through the real ALSA capture path: ALSA's `file` plugin (slave null, infile the raw S32_LE
    samples, format raw) from this test's own configuration (ALSA_CONFIG_PATH); it neither paces
    nor ends, so the component stops after the known frame count (--frames);
  - from the same samples as a WAV file (PCM 32) and as a CSV of time,acceleration (--file).

a0 and ω_d at each amplitude gate's end are compared with the simulated chain's (the rig's
VibrationChain on the displacement, its noise off) over the developed chatter. Then, in a halrun
session of about 2 s, the component replays the last 1.5 s as a WAV in real time with its pins
netted to lathectl_modfeed's a0-um and omega-d-Hz, which end at --print's last row.
The same samples as FLOAT_LE, and as S16_LE in the second of two interleaved channels, give
the same a0 and ω_d. Refusals (a bad CSV row, a channel the WAV lacks, no sensitivity, no file,
no device): one line naming the file and line, exit 2.

  vibsensor_test.py SOURCE_DIR WORK_DIR     (env VIBSENSOR, VIBSENSOR_RECORD: the two programs)
"""

import os
import re
import subprocess
import sys
import wave

import numpy as np

RATE = 48000
SENSITIVITY = 0.0102   # V per m/s², a 100 mV/g IEPE accelerometer
FULL_SCALE = 2.0       # V at the interface's digital full scale
SECONDS = 5.0
# s: the developed chatter the outputs are compared over (the module engages 2.3 s after the
# contact and holds a0 at 6–9 µm until about 5.5 s, when it quenches it)
WINDOW = (4.0, 5.0)


def scenario(src):
    """b_twin_feed_division for SECONDS at 48 kHz, 1 mm deep, the chain's noise off."""
    text = open(os.path.join(src, "examples/scenarios/b_twin_feed_division.toml")).read()
    text = re.sub(r"\[run\][^\[]*", "[run]\nduration_s = %g\nstep_s = %.17g\n"
                  "record_interval_s = 1e-3\nseed = 1\n\n" % (SECONDS, 1 / RATE), text)
    text = text.replace("depth_mm = [0.5, 0.5]", "depth_mm = [1.0, 1.0]")
    text = text.replace("z_end_mm = 320", "z_end_mm = 259")  # the cut within SECONDS
    text = text.replace("[vibration_sensor]\n", "[vibration_sensor]\nnoise_um = 0\n")
    return re.sub(r"^\[study\]\n(?:(?!\[).*\n?)*", "", text, flags=re.M)


def print_rows(cmd, env=None):
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, env=env, timeout=120)
    rows = np.loadtxt(out.stdout.splitlines()[1:], delimiter=",", ndmin=2)
    return out.stdout, rows, out.stderr


def hal_session(src, work, sc, samples, common):
    """The recording's last 1.5 s replayed by the HAL component into lathectl_modfeed's pins."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import halrun_test as H
    tail = os.path.join(work, "tail.wav")
    with wave.open(tail, "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(4)
        w.setframerate(RATE)
        w.writeframes(samples[-int(1.5 * RATE):].tobytes())
    _, rows, _ = print_rows(common + ["--file", tail])
    args = " ".join(a for a in common if a != "--print")
    hal = "\n".join([
        "loadrt threads name1=servo period1=1000000",
        "loadrt lathectl_modfeed scenario=%s" % H.rt_path(src, sc),
        "addf lathectl-modfeed servo",
        "loadusr -W %s --file %s" % (args, tail),
        "net vib-a0 lathectl-vibsensor.a0-um => lathectl-modfeed.a0-um",
        "net vib-fd lathectl-vibsensor.omega-d-Hz => lathectl-modfeed.omega-d-Hz",
        "start",
        "loadusr -w sleep 2.5",
        "show pin lathectl-vibsensor",
        "show pin lathectl-modfeed.a0-um",
        "show pin lathectl-modfeed.omega-d-Hz",
        "stop", ""])
    rc, log = H.halrun(hal, work, "vibsensor")
    assert rc == 0, log

    def pin(name):
        m = re.search(r"\s(\S+)\s+%s(?:\s|$)" % re.escape(name), log, re.M)
        assert m, name + " not shown:\n" + log
        v = m.group(1)
        return {"TRUE": 1.0, "FALSE": 0.0}.get(v) if v in ("TRUE", "FALSE") else \
            float(int(v, 16) if v.startswith("0x") else v)
    last = rows[-1]
    print("HAL: a0-um %g, omega-d-Hz %g at modfeed (--print's last row: %g, %g), running %d,"
          " frames %d" % (pin("lathectl-modfeed.a0-um"), pin("lathectl-modfeed.omega-d-Hz"),
                          last[1], last[2], pin("lathectl-vibsensor.running"),
                          pin("lathectl-vibsensor.frames")))
    assert pin("lathectl-vibsensor.frames") == int(1.5 * RATE)
    assert pin("lathectl-vibsensor.running") == 0
    assert pin("lathectl-modfeed.a0-um") == last[1] and last[1] > 5
    assert pin("lathectl-modfeed.omega-d-Hz") == last[2]


def other_formats(work, vibsensor, common, samples, s32_rows):
    """The device's other formats through the same plugin: FLOAT_LE mono, and S16_LE as the
    second of two interleaved channels (the first a different signal): within one ADC step and
    the detector's resolution of the S32 rows, nearly all gates equal."""
    for fmt, channels, data in (
            ("FLOAT_LE", 1, (samples / 2.0 ** 31).astype("<f4")),
            ("S16_LE", 2, np.column_stack([(samples[::-1] >> 16), samples >> 16]).astype("<i2"))):
        raw = os.path.join(work, "rec-%s.raw" % fmt)
        data.tofile(raw)
        conf = os.path.join(work, "asound-%s.conf" % fmt)
        open(conf, "w").write('pcm.lathectl_rec {\n  type file\n  slave.pcm { type null }\n'
                              '  file "/dev/null"\n  infile "%s"\n  format "raw"\n}\n' % raw)
        _, rows, _ = print_rows(
            common + ["--device", "lathectl_rec", "--rate", str(RATE), "--format", fmt,
                      "--channels", str(channels), "--channel", str(channels - 1),
                      "--frames", str(len(samples))], dict(os.environ, ALSA_CONFIG_PATH=conf))
        da0, df = rows[:, 1] - s32_rows[:, 1], rows[:, 2] - s32_rows[:, 2]
        print("%s (%d channel(s)): a0 equal in %d of %d gates, max |%.0f| um; omega_d max |%.0f| Hz"
              % (fmt, channels, (da0 == 0).sum(), len(rows), np.abs(da0).max(), np.abs(df).max()))
        assert len(rows) == len(s32_rows) and np.abs(da0).max() <= 1 and np.abs(df).max() <= 5
        assert (da0 == 0).mean() > 0.9


def bad_input(work, vibsensor, wav):
    """Refusals: one line naming the file (and line), exit 2, no output rows."""
    bad = os.path.join(work, "bad.csv")
    open(bad, "w").write("time_s,acceleration_m_s2\n0,1\n2e-5,x\n")
    cases = [([bad], bad + ":3: expected a row `time_s,acceleration_m_s2` of two numbers"),
             ([wav, "--channel", "1", "--sensitivity", "0.01"],
              wav + ": WAV: channel 1 asked for, the file has 1 (counted from 0)"),
             ([wav], "--sensitivity V_per_m_s2 (> 0) is required with --device or a WAV"),
             ([os.path.join(work, "none.wav"), "--sensitivity", "0.01"],
              os.path.join(work, "none.wav") + ": no such file (expected a signal (WAV))")]
    for args, message in cases:
        p = subprocess.run([vibsensor, "--print", "--file"] + args, capture_output=True, text=True)
        assert p.returncode == 2 and p.stdout == "", (args, p.returncode, p.stdout)
        assert p.stderr.strip() == "lathectl_vibsensor: " + message, p.stderr
    p = subprocess.run([vibsensor, "--print", "--device", "lathectl_no_such_pcm", "--sensitivity",
                        "0.01"], capture_output=True, text=True)
    assert p.returncode == 2 and "ALSA device lathectl_no_such_pcm: open:" in p.stderr, p.stderr


def main():
    src, work = (os.path.abspath(a) for a in sys.argv[1:3])
    vibsensor, record = (os.path.abspath(os.environ[v]) for v in ("VIBSENSOR", "VIBSENSOR_RECORD"))
    os.makedirs(work, exist_ok=True)
    sc = os.path.join(work, "b_record.toml")
    open(sc, "w").write(scenario(src))
    subprocess.run([record, sc, work, str(SENSITIVITY), str(FULL_SCALE)], check=True,
                   stdout=subprocess.DEVNULL, timeout=600)
    raw, wav, csv = (os.path.join(work, "rec." + e) for e in ("raw", "wav", "csv"))
    samples = np.fromfile(raw, dtype="<i4")
    assert np.max(np.abs(samples)) < 2 ** 31 * 0.9, "the recording would clip"
    with wave.open(wav, "wb") as w:  # PCM 32, the same samples
        w.setnchannels(1)
        w.setsampwidth(4)
        w.setframerate(RATE)
        w.writeframes(samples.tobytes())
    np.savetxt(csv, np.column_stack([np.arange(len(samples)) / RATE,
                                     samples * FULL_SCALE / SENSITIVITY / 2 ** 31]),
               delimiter=",", fmt="%.17g", header="time_s,acceleration_m_s2", comments="")
    conf = os.path.join(work, "asound.conf")
    open(conf, "w").write('pcm.lathectl_rec {\n  type file\n  slave.pcm { type null }\n'
                          '  file "/dev/null"\n  infile "%s"\n  format "raw"\n}\n' % raw)
    env = dict(os.environ, ALSA_CONFIG_PATH=conf)
    common = [vibsensor, "--scenario", sc, "--sensitivity", str(SENSITIVITY), "--full-scale",
              str(FULL_SCALE), "--print"]
    alsa_text, alsa, alsa_err = print_rows(
        common + ["--device", "lathectl_rec", "--rate", str(RATE), "--format", "S32_LE",
                  "--frames", str(len(samples))], env)
    wav_text, from_wav, _ = print_rows(common + ["--file", wav])
    _, from_csv, _ = print_rows(common + ["--file", csv])
    assert "0 overruns, 0 clipped" in alsa_err, alsa_err
    # The ALSA path and the WAV file carry the same samples into the same chain: the same rows.
    assert alsa_text == wav_text, "ALSA and WAV differ"
    # The CSV's values are the samples' m/s² (to 17 digits): the same a0 and ω_d.
    assert np.allclose(from_csv, from_wav, rtol=0, atol=1e-6), "CSV and WAV differ"

    # Against the simulated chain, gate by gate (both publish at the gates' ends, every 2400
    # samples; the rig's chain samples the displacement at 1e-4 s, this one the acceleration at
    # 48 kHz).
    sim = np.loadtxt(os.path.join(work, "sim.csv"), delimiter=",", skiprows=1, ndmin=2)
    n = min(len(sim), len(alsa))
    assert np.allclose(sim[:n, 0], alsa[:n, 0]), "the gates are not aligned"
    sim, alsa = sim[:n], alsa[:n]
    win = (alsa[:, 0] > WINDOW[0] + 1e-9) & (alsa[:, 0] <= WINDOW[1] + 1e-9)
    da0 = alsa[win, 1] - sim[win, 1]
    dfreq = alsa[win, 2] - sim[win, 2]
    print("gates compared: %d (t %.2f … %.2f s)" % (win.sum(), *WINDOW))
    print("a0 [um]: ALSA mean %.3f, simulated chain mean %.3f; difference mean %+.3f, max |%.3f|"
          % (alsa[win, 1].mean(), sim[win, 1].mean(), da0.mean(), np.abs(da0).max()))
    print("the same a0 in %d of %d gates, the same omega_d in %d"
          % ((da0 == 0).sum(), win.sum(), (dfreq == 0).sum()))
    print("omega_d [Hz]: ALSA mean %.2f, simulated chain mean %.2f; difference max |%.2f|"
          % (alsa[win, 2].mean(), sim[win, 2].mean(), np.abs(dfreq).max()))
    for row_a, row_s in zip(alsa[win], sim[win]):
        print("  t %.2f  a0 %.0f / %.0f um   f %.1f / %.1f Hz"
              % (row_a[0], row_a[1], row_s[1], row_a[2], row_s[2]))
    assert alsa[win, 1].min() > 5, "no developed chatter in the window"
    # One ADC step (1 um: the sampled peak, the acceleration's high-pass) and the detector's
    # resolution 1/(2·gate) = 5 Hz.
    assert np.abs(da0).max() <= 1.0 + 1e-9, da0
    assert np.abs(dfreq).max() <= 5.0 + 1e-9, dfreq
    print("vibsensor: ALSA, WAV and CSV paths agree with the simulated chain")
    other_formats(work, vibsensor, common, samples, from_wav)
    bad_input(work, vibsensor, wav)
    hal_session(src, work, sc, samples, common)


if __name__ == "__main__":
    main()
