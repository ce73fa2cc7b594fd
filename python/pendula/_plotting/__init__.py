"""The figure builders behind ``pendula.figures`` (private).

- ``base``: the text's constants, shared helpers and ``FigureUnavailable``;
- ``text_figures``: the text's own figures;
- ``extra_figures``: the figures this package adds (figA*).

``pendula.plots`` (drawing primitives: basin map, work-precision diagram),
``pendula.motion_plots`` (``plot_motion``) and ``pendula.figures`` (the
registry of figures) are the public faces; matplotlib is imported only when a
figure is drawn.
"""
