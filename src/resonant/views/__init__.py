"""Layer 6, the views: text summaries, LaTeX/HTML for Jupyter, MathML and plots.  They read
results and compute nothing new."""
