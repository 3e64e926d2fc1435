"""The yardstick page of the load test: a template, four sliders and two HoloViews plots.

Served by the same ``panel serve`` as the explorer (``benchmarks/loadtest.py``
adds this file), it tells what an ordinary small Panel page costs the server
per session, on this machine, under the same load; the explorer's cost per
session is compared with it (goal: at most twice). Everything is built per
session (this script runs once per session).
"""

import numpy as np
import panel as pn
import holoviews as hv

hv.extension("bokeh")
pn.extension(sizing_mode="stretch_width")

x = np.linspace(0.0, 2.0 * np.pi, 200)
amplitude = pn.widgets.FloatSlider(name="amplitude", start=0.1, end=2.0, value=1.0)
frequency = pn.widgets.FloatSlider(name="frequency", start=0.5, end=5.0, value=1.0)
phase = pn.widgets.FloatSlider(name="phase", start=0.0, end=np.pi, value=0.0)
damping = pn.widgets.FloatSlider(name="damping", start=0.0, end=1.0, value=0.1)


def wave(amplitude, frequency, phase, damping):
    y = amplitude * np.exp(-damping * x) * np.sin(frequency * x + phase)
    return hv.Curve((x, y), "x", "y").opts(responsive=True, height=300, title="wave")


def spectrum(amplitude, frequency, phase, damping):
    k = np.arange(1, 21)
    return hv.Scatter((k, amplitude / (1.0 + (k - frequency) ** 2 + damping)), "k", "power").opts(
        responsive=True, height=300, size=6, title="spectrum")


widgets = dict(amplitude=amplitude, frequency=frequency, phase=phase, damping=damping)
template = pn.template.BootstrapTemplate(title="Yardstick", sidebar=[amplitude, frequency, phase, damping])
template.main.append(pn.Row(hv.DynamicMap(pn.bind(wave, **widgets)), hv.DynamicMap(pn.bind(spectrum, **widgets))))
template.servable()
