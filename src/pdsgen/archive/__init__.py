"""A directory of PDS products as an archive holds them: the names and rules of a delivery's
layout (layout.py) and the grouping of a directory's files into data products, previews and
documents (scan.py).

Below the three folders that use them - deliver/ (which writes a delivery), review/ (which
shows a directory of products) and validate/ (whose DLV rules check a delivery) - so that
each of those imports them one way: deliver calls the review page, and the validator checks
what deliver wrote, without either importing the other back.
"""
