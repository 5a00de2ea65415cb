"""Recording: a built app run frame by frame into a web page, a CSV of its quantities and a picture.

The export, the picture drawn without a browser, and the CSV columns scenes report.
"""
